//! `areawarp report --quick` end to end: it runs every study, writes
//! `index.md`, a CSV per table, and figures that are valid and non-trivial.

use areawarp_lab::figures::{FigureKind, verify_figure};
use areawarp_lab::studies::paper_figures::PaperFigures;
use std::process::Command;

#[test]
fn quick_report_writes_tables_csv_and_valid_figures() {
    let dir = std::env::temp_dir().join(format!("areawarp-report-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_areawarp"))
        .args(["report", "--quick", "--out"])
        .arg(&dir)
        .output()
        .expect("run areawarp report");
    assert!(
        out.status.success(),
        "report failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let index = std::fs::read_to_string(dir.join("index.md")).expect("index.md");
    assert!(
        index.starts_with("# areawarp report\n\n## Summary"),
        "index.md opens with the summary"
    );
    for section in [
        "Warps at a glance",
        "Shao",
        "|---|",
        "| paper | where | claim | verdict (per-receiver) | verdict (image) |",
        "### Verdicts that changed from the previous report",
        "#### Departures from the papers' setups",
        "# 2. Ureña 2000",
        "The bias of the allocation rule",
        "![Figure 1: ",
        "*Figure 1.*",
        // Issue 11: equal time by CPU time, cubic vs Newton, the glossy
        // MIS rows, Shao–Badler intervals, area sampling's robust curve.
        "### Equal time: error against the CPU time spent per receiver",
        "#### Equal time, no occluders",
        "#### Equal time, 3 occluders",
        "| projected polygon (cubic only) |",
        "#### Cubic-only inversion of the projected polygon: bias in the irradiance",
        "| cubic − Newton (same points) |",
        "### MIS on a glossy (Phong) receiver",
        "| light sampler | RMS(+MIS) / RMS(alone) | 95% interval |",
        "Each ratio with its 95% interval",
        "### Area sampling's heavy tail",
        // Issue 11 item 3 for the adaptive study: its equal-time table,
        // the break-even cost, Ureña's cost claims in the summary; the
        // glossy MIS question in the summary.
        "#### Equal time: cost per estimate and efficiency",
        "**When is adaptive sampling worth its cost?**",
        "| Ureña 2000 | Ureña 2000, §5 (last paragraph) | adaptive sampling takes longer than stratified sampling",
        "| Arvo 2001 (our question) | our question (Arvo 2001, ch. 2",
        "on a glossy (Phong) receiver, does combining each light sample with a BRDF sample",
    ] {
        assert!(index.contains(section), "index.md lacks {section:?}");
    }
    // Issue 6's figures and tables, by name: the papers' sample
    // distributions, the speed–accuracy Pareto plot, RMS error against spp,
    // the f32 error maps, and the light-sampling cost table.
    for name in [
        "samples_spherical_triangle_random.svg",
        "samples_spherical_triangle_jittered.svg",
        "samples_projected_polygon_jittered.svg",
        "samples_spherical_rectangle_directions.svg",
        "samples_spherical_rectangle_points.svg",
        "speed_pareto.svg",
        "speed_pareto_mpfr.svg",
        "variance_jittered.svg",
        "solid_angle_f32_error_uv.svg",
        "light_cost.csv",
        "variance_adaptive.svg",
        "variance_adaptive_curves.csv",
        "variance_adaptive_occluded.svg",
        "samples_spherical_triangle_jittered.png",
        "solid_angle_f32_error_uv.png",
        "sample_figures.csv",
        "equal_time.svg",
        "equal_time_occluded.svg",
        "equal_time.csv",
        "equal_time_adaptive.svg",
        "equal_time_adaptive_occluded.svg",
        "variance_glossy.svg",
        "variance_glossy_curves.csv",
        "variance_area_robust.svg",
        // Issue 11's rendered images: Ureña, Fajardo & King 2013 Fig. 4
        // and 6, Ureña 2000 Fig. 9, and their errors per image.
        "images_ufk13.png",
        "images_ufk13_mis.png",
        "images_urena2000.png",
        "images_errors.csv",
    ] {
        assert!(dir.join(name).is_file(), "the report did not write {name}");
    }
    // Issue 11's re-made paper figures: written, each shown once in its
    // own paper's section, with a numbered caption and a descriptive alt
    // text (not the file name).
    let sections = [
        (
            "ufk2013_",
            "# 1. Ureña, Fajardo & King 2013",
            "# 2. Ureña 2000",
        ),
        ("urena2000_", "# 2. Ureña 2000", "# 3. Arvo"),
        ("arvo2001_", "# 3. Arvo", "# 4. Shao"),
        ("shao_badler1996_", "# 4. Shao", "# 5. The maps"),
    ];
    assert!(dir.join("paper_figures.csv").is_file());
    for stem in PaperFigures::figure_stems() {
        for ext in ["svg", "png"] {
            let name = format!("{stem}.{ext}");
            assert!(dir.join(&name).is_file(), "the report did not write {name}");
        }
        let link = format!("({stem}.svg)");
        assert_eq!(index.matches(&link).count(), 1, "{stem} shown once");
        let at = index.find(&link).unwrap();
        let (_, start, end) = sections
            .iter()
            .find(|(prefix, _, _)| stem.starts_with(prefix))
            .unwrap_or_else(|| panic!("{stem}: no section"));
        let (lo, hi) = (index.find(start).unwrap(), index.find(end).unwrap());
        assert!(lo < at && at < hi, "{stem} is not in the section {start:?}");
        let alt_start = index[..at].rfind("![Figure ").expect("a numbered alt text");
        let alt = &index[alt_start..at];
        assert!(
            alt.split_whitespace().count() >= 8 && !alt.contains(".svg"),
            "{stem}: alt text {alt:?}"
        );
        assert!(
            index.contains(&format!("(`{stem}.svg`)")),
            "{stem}: no caption line"
        );
    }
    // Each rendered-image figure sits beside the table it illustrates,
    // with a numbered caption and an alt text that describes it.
    let pos = |s: &str| {
        index
            .find(s)
            .unwrap_or_else(|| panic!("index.md lacks {s:?}"))
    };
    let ground = pos("### Rendered images (Ureña, Fajardo & King 2013, Fig. 4 and 6)");
    assert!(pos("### Relative RMS error, jittered points, all receivers") < ground);
    assert!(ground < pos("### Samples at equal error"));
    let triptych = pos("### Rendered images at 36 spp (Ureña 2000, Fig. 9)");
    assert!(pos("### Adaptive vs stratified (Ureña 2000, Fig. 9: occluders removed)") < triptych);
    assert!(triptych < pos("### Adaptive vs stratified with occluders"));
    for (file, section) in [
        ("images_ufk13.png", ground),
        ("images_ufk13_mis.png", ground),
        ("images_urena2000.png", triptych),
    ] {
        let link = pos(&format!("]({file})"));
        assert!(link > section, "{file} is not in its section");
        let line = index[..link].rsplit('\n').next().unwrap();
        assert!(
            line.starts_with("![Figure ") && line.split_whitespace().count() > 12,
            "{file}: alt text {line:?}"
        );
        let caption = &index[link..];
        let caption = &caption[caption.find("*Figure ").expect("a caption")..];
        let caption = caption.lines().next().unwrap();
        assert!(
            caption.contains("signed error") && caption.contains(&format!("(`{file}`)")),
            "{file}: caption {}",
            &caption[..caption.len().min(200)]
        );
        let check = verify_figure(&dir.join(file)).unwrap();
        assert!(
            check.width >= 400 && check.distinct_colors >= 50 && check.dark_pixels >= 1000,
            "{file}: {check:?}"
        );
    }
    // The adaptive study's equal-time figures, in the Ureña 2000 section,
    // after its tables.
    let urena = (pos("# 2. Ureña 2000"), pos("# 3. Arvo"));
    for (file, table) in [
        (
            "equal_time_adaptive.svg",
            "### Adaptive vs stratified (Ureña 2000, Fig. 9: occluders removed)",
        ),
        (
            "equal_time_adaptive_occluded.svg",
            "### Adaptive vs stratified with occluders",
        ),
    ] {
        let at = pos(&format!("]({file})"));
        assert!(
            urena.0 < at && at < urena.1,
            "{file} not in the Ureña 2000 section"
        );
        assert!(pos(table) < at, "{file} before its table");
        assert_eq!(
            index.matches(&format!("]({file})")).count(),
            1,
            "{file} shown once"
        );
    }
    // Every numbered figure's alt text describes it and differs from its
    // caption's title.
    let mut alts = std::collections::HashMap::new();
    for piece in index.split("![Figure ").skip(1) {
        let (n, rest) = piece.split_once(": ").expect("numbered alt text");
        let alt = &rest[..rest.find("](").expect("a link")];
        alts.insert(n.to_string(), alt.to_string());
    }
    let mut captions = 0;
    for line in index.lines().filter(|l| l.starts_with("*Figure ")) {
        for piece in line.split("*Figure ").skip(1) {
            let (n, rest) = piece.split_once(".* ").expect("numbered caption");
            let title = &rest[..rest.rfind(" (`").expect("a file name")];
            let alt = alts
                .get(n)
                .unwrap_or_else(|| panic!("figure {n}: no alt text"));
            assert_ne!(alt, title, "figure {n}: alt text equals the title");
            assert!(
                alt.split_whitespace().count() >= 8 && !alt.starts_with("image file"),
                "figure {n}: alt text {alt:?}"
            );
            captions += 1;
        }
    }
    assert!(captions >= 20, "only {captions} captions");
    let errors = std::fs::read_to_string(dir.join("images_errors.csv")).unwrap();
    assert!(errors.contains("images_urena2000.png,\"adaptive K=0.001\",36,"));
    assert!(errors.contains("images_ufk13_mis.png,rectangle+MIS(balance),16,"));
    let mut csv = 0;
    let mut figures = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        match path.extension().and_then(|e| e.to_str()) {
            Some("csv") => {
                // A header, and data rows (tables of failures may be empty).
                let text = std::fs::read_to_string(&path).unwrap();
                assert!(text.lines().count() >= 1, "{} is empty", path.display());
                if text.lines().count() >= 2 {
                    csv += 1;
                }
            }
            Some("svg") | Some("png") => {
                let check =
                    verify_figure(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                match check.kind {
                    // Data drawn, and text: a title, axis labels, ticks.
                    FigureKind::Svg => assert!(
                        check.marks >= 2 && check.texts >= 4,
                        "{}: {} marks, {} texts",
                        path.display(),
                        check.marks,
                        check.texts
                    ),
                    // Colours, and the dark pixels of axes and text.
                    FigureKind::Png => assert!(
                        check.distinct_colors >= 2 && check.dark_pixels >= 200,
                        "{}: {check:?}",
                        path.display()
                    ),
                }
                let name = path.file_name().unwrap().to_str().unwrap();
                assert!(index.contains(name), "index.md does not show {name}");
                figures += 1;
            }
            _ => {}
        }
    }
    assert!(csv >= 5, "only {csv} CSV files with data");
    assert!(figures >= 10, "only {figures} figures");
    let _ = std::fs::remove_dir_all(&dir);
}
