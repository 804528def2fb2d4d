//! Figures beside the tables they illustrate: a study's Markdown that does
//! not show its figures gets each one inserted, on a line of its own (so
//! the report numbers and captions it), right after the first table that
//! follows the figure's *anchor* (text of a heading).
//! Figures without an anchor, or whose anchor is absent, are left for the
//! end of the section ([`super::report`]'s figure links).

use crate::figures::Figure;
use std::path::Path;

/// `md` with each figure whose file name `anchor_of` maps to a text found
/// in a heading of `md` inserted after the end of the first table (a run of
/// lines starting with `|`) following that line. Figures sharing a table
/// keep their order. The file names are relative to `out`.
pub fn place_figures(
    md: &str,
    out: &Path,
    figs: &[Figure],
    anchor_of: impl Fn(&str) -> Option<String>,
) -> String {
    let mut lines: Vec<String> = md.lines().map(str::to_string).collect();
    // Insertions per line index (after that line), in figure order.
    let mut after: Vec<Vec<String>> = vec![Vec::new(); lines.len()];
    for f in figs {
        let rel = f.path.strip_prefix(out).unwrap_or(&f.path);
        let name = rel.display().to_string();
        if md.contains(&format!("({name})")) {
            continue;
        }
        let Some(anchor) = anchor_of(&name) else {
            continue;
        };
        let Some(start) = lines
            .iter()
            .position(|l| l.starts_with('#') && l.contains(&anchor))
        else {
            continue;
        };
        let Some(first) = (start + 1..lines.len()).find(|&i| lines[i].starts_with('|')) else {
            continue;
        };
        let last = (first..lines.len())
            .take_while(|&i| lines[i].starts_with('|'))
            .last()
            .unwrap_or(first);
        after[last].push(format!("![{}]({name})", f.title));
    }
    let mut s = String::with_capacity(md.len() + 512);
    for (i, line) in lines.drain(..).enumerate() {
        s.push_str(&line);
        s.push('\n');
        for img in &after[i] {
            s.push('\n');
            s.push_str(img);
            s.push('\n');
        }
    }
    s
}

/// The anchors of the variance study's figures: each error curve beside
/// its table (all receivers, near the light), the MIS heuristics, the
/// occluded curves, the error-vs-distance scatter beside the first
/// near-light table. Other figures (attached sections') have none.
pub fn variance_anchor(name: &str) -> Option<String> {
    let stem = name.strip_suffix(".svg")?.strip_prefix("variance_")?;
    if stem == "heuristics" {
        return Some("MIS heuristics".into());
    }
    if stem == "distance" {
        return Some("points, the ".into());
    }
    if stem.starts_with("occluded_") {
        return Some("With occluders".into());
    }
    if let Some(set) = stem.strip_suffix("_near") {
        return Some(format!("Relative RMS error, {set} points, the "));
    }
    Some(format!("Relative RMS error, {stem} points, all receivers"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn fig(name: &str, title: &str) -> Figure {
        Figure {
            path: PathBuf::from("/r").join(name),
            bytes: 1,
            marks: 1,
            width: 1,
            height: 1,
            title: title.into(),
            alt: String::new(),
        }
    }

    #[test]
    fn figures_go_after_the_table_that_follows_their_anchor() {
        let md = "## S\n\n### A\n\ntext\n\n| a |\n|---|\n| 1 |\n\nmore\n\n### B\n\n| b |\n|---|\n";
        let figs = [
            fig("x.svg", "X"),
            fig("y.svg", "Y"),
            fig("z.svg", "Z"),
            fig("w.svg", "W"),
        ];
        let out = place_figures(md, Path::new("/r"), &figs, |n| match n {
            "x.svg" | "y.svg" => Some("### A".into()),
            "z.svg" => Some("### B".into()),
            "w.svg" => Some("### missing".into()),
            _ => None,
        });
        let x = out.find("![X](x.svg)").expect("x placed");
        let y = out.find("![Y](y.svg)").expect("y placed");
        assert!(out.find("| 1 |").unwrap() < x && x < y && y < out.find("more").unwrap());
        assert!(out.find("| b |").unwrap() < out.find("![Z](z.svg)").unwrap());
        assert!(!out.contains("w.svg"), "no anchor: left for the end");
        // Each image on a line of its own (captioned by the report).
        assert!(out.contains("\n\n![X](x.svg)\n\n![Y](y.svg)\n"));
        // Figures already shown are not repeated.
        let again = place_figures(&out, Path::new("/r"), &figs, |_| Some("### A".into()));
        assert_eq!(again.matches("x.svg").count(), 1);
    }

    #[test]
    fn variance_figures_have_their_tables() {
        assert_eq!(
            variance_anchor("variance_jittered.svg").as_deref(),
            Some("Relative RMS error, jittered points, all receivers")
        );
        assert_eq!(
            variance_anchor("variance_sobol_near.svg").as_deref(),
            Some("Relative RMS error, sobol points, the ")
        );
        assert_eq!(
            variance_anchor("variance_occluded_jittered.svg").as_deref(),
            Some("With occluders")
        );
        assert_eq!(variance_anchor("other.svg"), None);
    }
}
