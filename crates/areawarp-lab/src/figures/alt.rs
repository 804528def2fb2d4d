//! Alt texts: a short description of what a figure plots and on which
//! axes, distinct from its title (which the report uses as the caption).

use super::{Axis, HeatMap, ImageGrid, Plot, Scale};

/// `label (log scale)` or the label alone.
fn axis(a: &Axis) -> String {
    let label = if a.label.is_empty() {
        "unlabelled axis"
    } else {
        a.label.as_str()
    };
    match a.scale {
        Scale::Log10 => format!("{label} (log scale)"),
        Scale::Linear => label.to_string(),
    }
}

/// Up to `k` names, then how many more.
fn names<'a>(it: impl Iterator<Item = &'a str>, k: usize) -> String {
    let all: Vec<&str> = it.filter(|s| !s.is_empty()).collect();
    let mut s = all.iter().take(k).copied().collect::<Vec<_>>().join(", ");
    if all.len() > k {
        s.push_str(&format!(" and {} more", all.len() - k));
    }
    s
}

impl Plot {
    /// The alt text of the plot drawn as `kind` ("Line chart", "Scatter
    /// plot"): the axes, the number of series with their names, and the
    /// bands if any.
    pub(crate) fn alt_text(&self, kind: &str) -> String {
        let listed = self.series.iter().filter(|s| !s.label.is_empty()).count();
        let bands = self.series.iter().any(|s| !s.band.is_empty());
        let mut s = format!(
            "{kind} of {} (vertical) against {} (horizontal)",
            axis(&self.y),
            axis(&self.x)
        );
        if listed > 0 {
            s.push_str(&format!(
                "; {listed} series: {}",
                names(self.series.iter().map(|s| s.label.as_str()), 6)
            ));
        }
        if bands {
            s.push_str("; shaded bands are confidence intervals");
        }
        s
    }
}

impl HeatMap {
    /// The alt text: the coloured quantity over the two axes, and the grid.
    pub(crate) fn alt_text(&self) -> String {
        let value = if self.value_label.is_empty() {
            "a value"
        } else {
            self.value_label.as_str()
        };
        format!(
            "Colour map of {value}{} over {} (horizontal) and {} (vertical), {} × {} cells, with a colour bar",
            if self.value_scale == Scale::Log10 {
                " (log colour scale)"
            } else {
                ""
            },
            axis(&self.x),
            axis(&self.y),
            self.cols,
            self.rows
        )
    }
}

impl ImageGrid {
    /// The alt text: how many false-colour panels, their titles, the axes
    /// and the colour scales.
    pub(crate) fn alt_text(&self) -> String {
        let panels: Vec<&str> = self
            .panels
            .iter()
            .flatten()
            .map(|p| p.title.as_str())
            .collect();
        format!(
            "Grid of {} false-colour images, {} per row ({}), each over {} (horizontal) and {} (vertical); colour bars: {}",
            panels.len(),
            self.columns,
            names(panels.iter().copied(), 8),
            axis(&self.x),
            axis(&self.y),
            names(self.scales.iter().map(|s| s.label.as_str()), 4)
        )
    }
}
