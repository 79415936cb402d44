//! `enginedyn kinematics`: the piston table the seeds print.

use crate::Failure;
use crate::args::KinematicsArgs;
use enginedyn_kinematics::Table;
use enginedyn_report::Figure;
use std::f64::consts::PI;
use std::fmt::Write as _;

const HEADER: &str =
    "crank_deg,coef_a,coef_b,coef_c,piston_x_m,piston_v_m_s,piston_a_m_s2,rod_angle_deg";

/// What `kinematics --out DIR` writes.
const FILES: [&str; 2] = ["kinematics.csv", "kinematics.svg"];

pub fn run(a: &KinematicsArgs) -> Result<(), Failure> {
    let loaded = enginedyn_session::Loaded::from_file(&a.engine)?;
    let engine = &loaded.engine;
    // Something in the way of an output is refused before the table is made.
    let out = crate::open_out(a.out.as_deref(), &FILES, "kinematics")?;
    let speed = enginedyn_session::speed::resolve_rpm(a.rpm, None, engine)?;
    if let Some(n) = &speed.note {
        crate::say(None, n);
    }
    crate::say_all(&engine.plausibility_notes(Some(speed.rpm)));
    let rpm = speed.rpm;
    let omega = rpm * PI / 30.0;
    let model = a.kinematics.model();
    let mech = engine.mechanism();
    let r = mech.r();
    // The printed table at 30° as the seeds print it; files at 0.1°; --step sets both.
    let table_step = a.step.unwrap_or(30.0);
    let file_step = a.step.unwrap_or(0.1);
    let fill = |step: f64| -> Result<(usize, Table), Failure> {
        let n = (360.0 / step).round();
        if !(step > 0.0) || (n * step - 360.0).abs() > 1e-9 || n < 1.0 {
            return Err(Failure::usage(format!(
                "--step {step}: the step must divide 360°"
            )));
        }
        // The table closes the revolution: 0..=360 as the seeds print it.
        let rows = n as usize + 1;
        let mut t = Table::default();
        mech.fill(model, 0.0, step.to_radians(), rows, &mut t)
            .map_err(|e| {
                Failure::usage(format!(
                    "{}: --kinematics {}: {e}",
                    a.engine.display(),
                    model.name()
                ))
            })?;
        Ok((rows, t))
    };
    let (rows, t) = fill(file_step)?;
    let step = file_step;
    let csv = || {
        let mut s = String::from(HEADER);
        s.push('\n');
        for k in 0..rows {
            let cells = [
                (k as f64 * step * 1e9).round() / 1e9,
                t.x[k] / r,
                t.dx[k] / r,
                t.d2x[k] / r,
                t.x[k],
                t.dx[k] * omega,
                t.d2x[k] * omega * omega,
                t.beta[k].to_degrees(),
            ];
            let cells: Vec<String> = cells
                .into_iter()
                .map(enginedyn_numerics::format::csv)
                .collect();
            let _ = writeln!(s, "{}", cells.join(","));
        }
        s
    };
    if a.csv {
        crate::emit(&csv());
    } else {
        let (rows, t) = fill(table_step)?;
        let step = table_step;
        let mut text = format!(
            "{}: {} kinematics, R = {:.4} mm, λ = {:.4}, {rpm:.0} rpm (ω = {omega:.3} rad/s)\n",
            engine.name(),
            model.name(),
            r * 1e3,
            mech.lambda()
        );
        let _ = writeln!(
            text,
            "{:>8} {:>9} {:>9} {:>9} {:>10} {:>9} {:>11} {:>9}",
            "φ deg", "A=x/R", "B=v/Rω", "C=a/Rω²", "x mm", "v m/s", "a m/s²", "β deg"
        );
        for k in 0..rows {
            let _ = writeln!(
                text,
                "{:>8.1} {:>9.4} {:>9.4} {:>9.4} {:>10.3} {:>9.3} {:>11.1} {:>9.3}",
                k as f64 * step,
                t.x[k] / r,
                t.dx[k] / r,
                t.d2x[k] / r,
                t.x[k] * 1e3,
                t.dx[k] * omega,
                t.d2x[k] * omega * omega,
                t.beta[k].to_degrees()
            );
        }
        crate::emit(&text);
    }
    if let Some(dir) = &out {
        let chart = enginedyn_report::kinematics_chart(
            format!(
                "{} — piston motion ({}), {rpm:.0} rpm",
                engine.name(),
                model.name()
            ),
            &t,
            r,
            step,
        );
        let figure = Figure::single(FILES[1], chart);
        let svg = figure.render().map_err(|e| Failure::data(e.to_string()))?;
        let [table, chart] = FILES.map(String::from);
        let files = vec![(table, csv().into_bytes()), (chart, svg.into_bytes())];
        crate::write_out_to(dir, &files, a.csv)?;
    }
    Ok(())
}
