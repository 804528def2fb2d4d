//! The report's first page: the verdict table for the five papers, the
//! machine, compiler and run time, and the verdicts that changed since the
//! previous report; and the numbering of the figures with their captions.

use crate::verdict::{Claim, Verdict, chi2_p_value};
use std::collections::HashMap;
use std::fmt::Write as _;

/// One row of the summary's verdict table.
#[derive(Clone, Debug)]
pub struct SummaryRow {
    /// The paper (short).
    pub paper: String,
    /// Where in the paper.
    pub source: String,
    /// The claim.
    pub claim: String,
    /// The verdict on the per-receiver metric (or the only one).
    pub verdict: Verdict,
    /// The verdict on the image metric, if the claim has a second one.
    pub verdict_image: Option<Verdict>,
    /// Where the numbers are (a claim id `C12` or a section).
    pub detail: String,
}

impl SummaryRow {
    /// Whether the row is our own question (its source starts with
    /// [`crate::verdict::OUR_QUESTION`]): answered yes / no, not counted
    /// among the papers' claims.
    pub fn is_our_question(&self) -> bool {
        self.source.starts_with(crate::verdict::OUR_QUESTION)
    }
}

/// The answer of an our-question row (`yes`, `yes, smaller`, `mixed`, `no`).
fn answer(v: Verdict) -> &'static str {
    match v {
        Verdict::Reproduced => "yes",
        Verdict::Qualitative => "yes, smaller",
        Verdict::Mixed => "mixed",
        Verdict::NotReproduced => "no",
        Verdict::NotMeasured => "not measured",
    }
}

/// The short name of the paper a source cites.
pub fn paper_of(source: &str) -> &'static str {
    if source.contains("Fajardo") {
        "Ureña, Fajardo & King 2013"
    } else if source.contains("Ureña 2000") {
        "Ureña 2000"
    } else if source.contains("Arvo 2001") {
        "Arvo 2001"
    } else if source.contains("Arvo 1995") {
        "Arvo 1995"
    } else if source.contains("Shao") {
        "Shao & Badler 1996"
    } else {
        "other"
    }
}

/// Summary rows from claims judged under both metrics (our own questions
/// and extensions left out); `C{k}` refers to the claims table.
pub fn rows_from_claims(pairs: &[(Claim, Claim)]) -> Vec<SummaryRow> {
    pairs
        .iter()
        .enumerate()
        .filter(|(_, (a, _))| !a.is_our_question())
        .map(|(k, (a, b))| SummaryRow {
            paper: paper_of(&a.source).to_string(),
            source: a.source.clone(),
            claim: a.statement.clone(),
            verdict: a.verdict,
            verdict_image: Some(b.verdict),
            detail: format!("C{}", k + 1),
        })
        .collect()
}

/// The machine: CPU model and logical CPUs (from `/proc/cpuinfo` where it
/// exists), OS and architecture.
pub fn machine() -> String {
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let model = cpuinfo
        .lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split(':').nth(1))
        .map_or("unknown CPU".to_string(), |m| m.trim().to_string());
    let cpus = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!(
        "{model}, {cpus} logical CPUs available to the process ({} {})",
        std::env::consts::OS,
        std::env::consts::ARCH
    )
}

/// The compiler that built this program (recorded by the build script).
pub fn compiler() -> &'static str {
    match option_env!("AREAWARP_RUSTC_VERSION") {
        Some(v) if !v.is_empty() => v,
        _ => "unknown rustc",
    }
}

/// The verdict rows of a previous report's claims table(s): claim text →
/// verdict text (per-receiver verdict for the new format).
pub fn previous_verdicts(index_md: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut columns: Option<usize> = None;
    for line in index_md.lines() {
        if line.starts_with("| source | claim | measured | verdict |") {
            columns = Some(4);
            continue;
        }
        if line.starts_with("| # | source | claim | measured | verdict (per-receiver)") {
            columns = Some(6);
            continue;
        }
        let Some(n) = columns else { continue };
        if !line.starts_with('|') {
            columns = None;
            continue;
        }
        if line.starts_with("|---") {
            continue;
        }
        let cells: Vec<&str> = line.trim_matches('|').split(" | ").map(str::trim).collect();
        if cells.len() < n {
            continue;
        }
        let (claim, verdict) = if n == 4 {
            (cells[1], cells[cells.len() - 1])
        } else {
            (cells[2], cells[cells.len() - 2])
        };
        // The old report listed some claims twice: keep the first.
        if !out.iter().any(|(c, _): &(String, String)| c == claim) {
            out.push((
                claim.to_string(),
                verdict.trim_matches('*').trim().to_string(),
            ));
        }
    }
    out
}

/// Why a verdict changed from `old` to `new` under the rule of
/// [`crate::verdict`].
fn why(old: &str, new: Verdict) -> &'static str {
    match (old, new) {
        ("reproduced", Verdict::Qualitative) => {
            "the paper's figure lies outside our 95% interval (the old rule accepted values within a factor of about 2)"
        }
        ("reproduced", Verdict::Mixed) => {
            "holds over all receivers but is significantly reversed near the light"
        }
        ("reproduced", Verdict::NotReproduced) => {
            "our interval does not show the claimed size (old rule: any reading within a factor 2)"
        }
        (o, Verdict::Reproduced) if o.starts_with("partly") => {
            "the paper's figure (or its threshold) is inside our 95% interval"
        }
        (o, Verdict::NotReproduced) if o.starts_with("partly") => {
            "the claim is about a size our interval excludes, or its effect reverses (the old label counted any partial agreement)"
        }
        (o, Verdict::Qualitative) if o.starts_with("partly") => "renamed: \"direction holds\"",
        _ => "the verdict rule and the measurement changed",
    }
}

/// The first words of a claim, for matching reworded rows.
fn key(claim: &str) -> String {
    claim
        .split(" (")
        .next()
        .unwrap_or(claim)
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == ' ')
        .collect::<String>()
        .to_lowercase()
}

/// The list of verdicts that changed from a previous report's, and the
/// previous rows with no counterpart (dropped, split or reworded).
pub fn changes_markdown(previous: &[(String, String)], claims: &[(Claim, Claim)]) -> String {
    if previous.is_empty() {
        return "No previous report in the output directory: no verdicts to compare.\n".to_string();
    }
    let mut s = String::new();
    let mut matched = vec![false; previous.len()];
    let _ = writeln!(
        s,
        "| claim | previous verdict | now (per-receiver / image) | why |\n|---|---|---|---|"
    );
    let mut changed = 0;
    for (k, (a, b)) in claims.iter().enumerate() {
        let ka = key(&a.statement);
        let Some(i) = previous
            .iter()
            .enumerate()
            .position(|(i, (c, _))| !matched[i] && (key(c) == ka || *c == a.statement))
        else {
            continue;
        };
        matched[i] = true;
        let old = previous[i].1.as_str();
        let now = a.verdict_text();
        if old != now {
            changed += 1;
            let _ = writeln!(
                s,
                "| C{}: {} | {} | {} / {} | {} |",
                k + 1,
                a.statement,
                old,
                now,
                b.verdict_text(),
                if a.is_our_question() {
                    "now labelled our question: the paper does not claim it"
                } else {
                    why(old, a.verdict)
                }
            );
        }
    }
    let gone: Vec<String> = previous
        .iter()
        .zip(&matched)
        .filter(|(_, m)| !**m)
        .map(|((c, v), _)| format!("- *{c}* (was **{v}**)"))
        .collect();
    let mut head = format!("{changed} verdicts changed from the previous report.\n\n");
    if changed == 0 {
        head = "No verdict changed from the previous report.\n\n".to_string();
        s.clear();
    }
    if !gone.is_empty() {
        let _ = writeln!(
            s,
            "\nPrevious rows split, reworded or dropped (see the claims table for their successors: per-sampler MIS rows, the balance heuristic judged with independent samples and asked of jittered points as our question, the Ureña 2000 claims without occluders and with them as our extension):\n\n{}\n",
            gone.join("\n")
        );
    }
    head + &s
}

/// The summary's verdict table.
pub fn verdict_table(rows: &[SummaryRow]) -> String {
    let mut s = String::from(
        "| paper | where | claim | verdict (per-receiver) | verdict (image) | numbers |\n|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let name = |v: Verdict| {
            if r.is_our_question() {
                answer(v)
            } else {
                v.name()
            }
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | **{}** | {} | {} |",
            r.paper,
            r.source,
            r.claim,
            name(r.verdict),
            r.verdict_image.map_or("–", name),
            r.detail
        );
    }
    s
}

/// The summary row for a χ² uniformity check: reproduced if the p-value of
/// the independent samples' χ² is at least 0.01 (uniform as claimed).
pub fn chi2_row(
    paper: &str,
    source: &str,
    claim: &str,
    chi2: f64,
    dof: f64,
    detail: &str,
) -> SummaryRow {
    let p = chi2_p_value(chi2, dof);
    SummaryRow {
        paper: paper.to_string(),
        source: source.to_string(),
        claim: format!("{claim} (χ² = {chi2:.2} on {dof:.0} d.o.f., p = {p:.3})"),
        verdict: if p >= 0.01 {
            Verdict::Reproduced
        } else {
            Verdict::NotReproduced
        },
        verdict_image: None,
        detail: detail.to_string(),
    }
}

/// Numbers the figures of `md` in order of appearance. `figures` maps a
/// file to its title (the caption) and its alt text (what it plots, on
/// which axes). Every image gets the alt text "Figure k: alt" — the alt
/// text written in the Markdown if it is descriptive (eight words or more,
/// not the file name, not the title), else the figure's own, else the file
/// name — and an image alone on its line a caption line below it,
/// "*Figure k.* title (`file`)". Returns the new Markdown and the number of
/// figures.
pub fn number_figures(md: &str, figures: &HashMap<String, (String, String)>) -> (String, usize) {
    let mut out = String::with_capacity(md.len() + 4096);
    let mut k = 0;
    let mut numbers: HashMap<String, usize> = HashMap::new();
    for line in md.lines() {
        let mut rest = line;
        let mut new_line = String::new();
        let mut captions = Vec::new();
        while let Some(start) = rest.find("![") {
            let Some(mid) = rest[start..].find("](") else {
                break;
            };
            let Some(end) = rest[start + mid..].find(')') else {
                break;
            };
            let alt = &rest[start + 2..start + mid];
            let file = &rest[start + mid + 2..start + mid + end];
            new_line.push_str(&rest[..start]);
            let n = *numbers.entry(file.to_string()).or_insert_with(|| {
                k += 1;
                k
            });
            let known = figures.get(file);
            let title = known
                .map(|f| f.0.clone())
                .filter(|t| !t.is_empty())
                .unwrap_or_else(|| {
                    if alt.is_empty() || alt == file {
                        file.to_string()
                    } else {
                        alt.to_string()
                    }
                });
            let title = title.replace(['[', ']'], "");
            let written = (alt.split_whitespace().count() >= 8 && alt != file && alt != title)
                .then(|| alt.to_string());
            let own = known
                .map(|f| f.1.clone())
                .filter(|a| !a.is_empty() && *a != title);
            let alt = written
                .or(own)
                .unwrap_or_else(|| format!("image file {file}"))
                .replace(['[', ']'], "");
            let _ = write!(new_line, "![Figure {n}: {alt}]({file})");
            captions.push(format!("*Figure {n}.* {title} (`{file}`)"));
            rest = &rest[start + mid + end + 1..];
        }
        new_line.push_str(rest);
        out.push_str(&new_line);
        out.push('\n');
        let alone = line.trim_start().starts_with("![") && !line.trim_start().starts_with('|');
        if alone && !captions.is_empty() {
            out.push('\n');
            out.push_str(&captions.join(" "));
            out.push('\n');
        }
    }
    (out, k)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_are_numbered_with_alt_texts_and_titled_captions() {
        let mut t = HashMap::new();
        t.insert(
            "a.svg".to_string(),
            (
                "Error against spp".to_string(),
                "Line chart of error against spp".to_string(),
            ),
        );
        t.insert(
            "c.svg".to_string(),
            ("C's title".to_string(), "C's own alt text".to_string()),
        );
        let (md, n) = number_figures(
            "text\n![a.svg](a.svg)\n| ![x](b.svg) | ![](a.svg) |\n![one two three four five six seven eight](c.svg)\n",
            &t,
        );
        assert_eq!(n, 3);
        assert!(md.contains(
            "![Figure 1: Line chart of error against spp](a.svg)\n\n*Figure 1.* Error against spp (`a.svg`)"
        ));
        assert!(md.contains(
            "| ![Figure 2: image file b.svg](b.svg) | ![Figure 1: Line chart of error against spp](a.svg) |"
        ));
        // A descriptive alt text written in the Markdown is kept, the
        // title captions it.
        assert!(md.contains(
            "![Figure 3: one two three four five six seven eight](c.svg)\n\n*Figure 3.* C's title (`c.svg`)"
        ));
    }

    #[test]
    fn previous_verdicts_are_read_from_both_formats() {
        let old = "| source | claim | measured | verdict |\n|---|---|---|---|\n| P | c1 | m | **reproduced** |\n\nx\n";
        assert_eq!(
            previous_verdicts(old),
            vec![("c1".to_string(), "reproduced".to_string())]
        );
        let new = "| # | source | claim | measured | verdict (per-receiver) | verdict (image) |\n|---|\n| C1 | P | c2 | m | **direction holds** | reproduced (flips) |\n";
        assert_eq!(
            previous_verdicts(new),
            vec![("c2".to_string(), "direction holds".to_string())]
        );
    }
}
