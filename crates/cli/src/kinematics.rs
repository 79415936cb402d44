//! `enginedyn kinematics`: the piston table the seeds print; the motion is
//! `enginedyn_session::kinematics`'s, the table, CSV and chart
//! `enginedyn_report`'s.

use crate::Failure;
use crate::args::KinematicsArgs;
use enginedyn_report::KINEMATICS_FILES as FILES;
use enginedyn_session::kinematics::{FILE_STEP_DEG, Kinematics, TABLE_STEP_DEG};

/// Runs `enginedyn kinematics`.
pub fn run(a: &KinematicsArgs) -> Result<(), Failure> {
    let loaded = enginedyn_session::Loaded::from_file(&a.engine)?;
    let engine = &loaded.engine;
    // Something in the way of an output is refused before the table is made.
    let out = crate::open_out(a.out.as_deref(), &FILES, "kinematics")?;
    let k = Kinematics::new(&loaded, a.rpm, a.kinematics.model())?;
    crate::say_all(&k.notes);
    let r = engine.mechanism().r();
    // The printed table at 30° as the seeds print it; files at 0.1°; --step sets both.
    let file_step = a.step.unwrap_or(FILE_STEP_DEG);
    let t = k.table(file_step)?;
    let csv = || enginedyn_report::kinematics_csv(&t, file_step, r, k.omega);
    if a.csv {
        crate::emit(&csv());
    } else {
        let step = a.step.unwrap_or(TABLE_STEP_DEG);
        let printed = k.table(step)?;
        crate::emit(&enginedyn_report::kinematics_table(
            engine, k.model, k.rpm, k.omega, &printed, step,
        ));
    }
    if let Some(dir) = &out {
        let svg = enginedyn_report::kinematics_svg(engine, k.model, k.rpm, &t, file_step)
            .map_err(|e| Failure::data(e.to_string()))?;
        let [table, chart] = FILES.map(String::from);
        let files = vec![(table, csv().into_bytes()), (chart, svg.into_bytes())];
        crate::write_out_to(dir, &files, a.csv)?;
    }
    Ok(())
}
