//! `areawarp`: the command-line program.
//!
//! - `areawarp eval [--precision f32|f64|mpfr:BITS] [--inverse] [FILE]`: a
//!   line-oriented evaluator of the warps, for scripts and cross-checks.
//! - `areawarp report [--out DIR] [--quick | --large]`: runs the precision, Jacobian and
//!   speed measurements over every warp and writes a Markdown report.

use areawarp_lab::cli;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "areawarp",
    version,
    about = "Area-preserving parametrizations: evaluate, check, report"
)]
struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Evaluate maps line by line: `MAP PARAMS… u v` → `MAP outputs…`.
    Eval {
        /// Arithmetic: f32, f64 or mpfr:BITS (BITS one of 64, 113, 128, 192, 256, 512, 1024);
        /// or auto:TOL: each spherical triangle or rectangle evaluated the cheapest way
        /// (f32, f32 output with f64 arithmetic, f64) predicted to stay within TOL.
        #[arg(long, default_value = "f64")]
        precision: String,
        /// Each line ends with a point instead of `u v`; print `MAP u v`.
        #[arg(long)]
        inverse: bool,
        /// Solid-angle maps: `robust` (default) or the papers' `literal`
        /// algorithms; `planar-triangle`: `fold` for Heitz's fold map;
        /// uniform-cone, ggx, beckmann, von-mises-fisher, hemisphere, phong,
        /// sphere: `closed` (the closed form, default), `derived` (from φ and
        /// the weight by quadrature) or `tabulated:TOL` (tabulated inverses,
        /// error at most TOL on the parameters of φ).
        #[arg(long, default_value = "robust", value_parser = parse_variant)]
        variant: String,
        /// projected-polygon: Newton steps after the Vandermonde cubic (default: to convergence).
        #[arg(long)]
        newton: Option<u32>,
        /// Input file (standard input when absent).
        file: Option<PathBuf>,
    },
    /// Run the checks and timings over every warp; write report/index.md.
    Report {
        /// Output directory.
        #[arg(long, default_value = "report")]
        out: PathBuf,
        /// A quick run: small sizes, seconds (for a look; the tests use it).
        #[arg(long, conflicts_with = "large")]
        quick: bool,
        /// A large run: 4× the runs of the variance studies and more
        /// samples and timing repetitions elsewhere (several minutes).
        #[arg(long)]
        large: bool,
    },
}

/// Accepts the values of `--variant`.
fn parse_variant(s: &str) -> Result<String, String> {
    if matches!(s, "robust" | "literal" | "fold")
        || cli::eval_recipe::RecipeVariant::parse(s).is_some()
    {
        Ok(s.to_string())
    } else {
        Err(format!(
            "expected robust, literal, fold, closed, derived or tabulated:TOL (TOL > 0), got {s:?}"
        ))
    }
}

fn main() -> ExitCode {
    let args = Args::parse();
    match args.command {
        Command::Eval {
            precision,
            inverse,
            variant,
            newton,
            file,
        } => {
            let opts = cli::eval::Options {
                inverse,
                literal: variant == "literal",
                fold: variant == "fold",
                newton,
                tolerance: None,
                recipe: cli::eval_recipe::RecipeVariant::parse(&variant).unwrap_or_default(),
            };
            cli::eval::main(&precision, opts, file.as_deref())
        }
        Command::Report { out, quick, large } => {
            let size = if quick {
                cli::report::Size::Quick
            } else if large {
                cli::report::Size::Large
            } else {
                cli::report::Size::Default
            };
            cli::report::main(&out, size)
        }
    }
}
