//! The single-grain crushing study on real outlines (issue 25 item 5, docs/lattice.md §6):
//! `n` outlines of a folder (e.g. the real gravel grains of `../shared/outlines/rhode-island`,
//! which the project does not copy) at the sizes, lattice and material of the report's study,
//! written to `<out>/results.json`; the report's "Crushable grains" section reads it from
//! `docs/report/crush/real/` when committed there, and never runs it.
//!
//!     cargo run --release -p validation --example crush_real -- \
//!         ../shared/outlines/rhode-island 30 docs/report/crush/real

use std::path::PathBuf;
use validation::crush;

fn main() -> Result<(), validation::error::Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [dir, n, out] = &args[..] else {
        return Err(validation::error::Error::Other(
            "usage: crush_real <outline folder> <number of grains> <output folder>".into(),
        ));
    };
    let dir = PathBuf::from(dir);
    let n: usize = n.parse().map_err(|_| {
        validation::error::Error::Other(format!("{n}: the number of grains is not a count"))
    })?;
    let plan = crush::plan_of_folder(&dir, n)?;
    let data = dir.parent().map(PathBuf::from).unwrap_or_default();
    let r = crush::run_in_temp(&plan, &data);
    let out = PathBuf::from(out);
    std::fs::create_dir_all(&out).map_err(validation::error::Error::io(&out))?;
    validation::page::write(&out, "results.json", &validation::page::json(&r))?;
    eprintln!(
        "{} runs, {} errors, {:.0} s; {}",
        r.rows.len(),
        r.errors.len(),
        r.total_wall_time_s,
        out.join("results.json").display()
    );
    Ok(())
}
