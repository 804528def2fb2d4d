//! Alt texts: a short description of what a figure plots and on which
//! axes, distinct from its title (which the report uses as the caption).

use super::{Axis, HeatMap, ImageGrid, Plot, Scale};

/// The label without its parenthetical remarks (alt texts stay short),
/// and `, log scale` for a log axis.
fn axis(a: &Axis) -> String {
    let mut label = String::new();
    let mut depth = 0usize;
    for c in a.label.chars() {
        match c {
            '(' => depth += 1,
            ')' => depth = depth.saturating_sub(1),
            _ if depth == 0 => label.push(c),
            _ => {}
        }
    }
    let label = label.split_whitespace().collect::<Vec<_>>().join(" ");
    let label = if label.is_empty() {
        "an unlabelled axis".to_string()
    } else {
        label
    };
    match a.scale {
        Scale::Log10 => format!("{label} (log scale)"),
        Scale::Linear => label,
    }
}

/// Up to `k` names, then how many more.
fn names<'a>(it: impl Iterator<Item = &'a str>, k: usize) -> String {
    let all: Vec<&str> = it.filter(|s| !s.is_empty()).collect();
    let mut s = all.iter().take(k).copied().collect::<Vec<_>>().join("; ");
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
            "{kind} plotting {} (up) against {} (across)",
            axis(&self.y),
            axis(&self.x)
        );
        if listed > 0 {
            s.push_str(&format!(
                "; {listed} series ({})",
                names(self.series.iter().map(|s| s.label.as_str()), 4)
            ));
        }
        if bands {
            s.push_str(", with shaded confidence bands");
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
            "Colour map of {value}{} over {} (across) and {} (up), {} × {} cells, with a colour bar",
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
            "Grid of {} false-colour images, {} per row ({}), each over {} (across) and {} (up); colour bars: {}",
            panels.len(),
            self.columns,
            names(panels.iter().copied(), 4),
            axis(&self.x),
            axis(&self.y),
            names(self.scales.iter().map(|s| s.label.as_str()), 4)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::Series;

    #[test]
    fn alt_texts_name_the_axes_and_series_without_remarks() {
        let plot = Plot::new(
            "Error of everything",
            Axis::log("spp (MIS: 2n rays)"),
            Axis::log("relative RMS (band: 95%)"),
        )
        .series(Series::new("a", vec![(1.0, 1.0)]).with_band(vec![(1.0, 0.5, 2.0)]))
        .series(Series::new("b", vec![(1.0, 1.0)]));
        assert_eq!(
            plot.alt_text("Line chart"),
            "Line chart plotting relative RMS (log scale) (up) against spp (log scale) (across); 2 series (a; b), with shaded confidence bands"
        );
        let bare = Plot::new("t", Axis::linear(""), Axis::linear("y"));
        assert!(bare.alt_text("Scatter plot").split_whitespace().count() >= 8);
        assert_eq!(names(["a", "b", "c"].into_iter(), 2), "a; b and 1 more");
    }
}
