//! `enginedyn kinematics`'s outputs: the piston table as printed (the seeds'
//! table), `kinematics.csv` and `kinematics.svg`. The motion itself is
//! `enginedyn_kinematics`'s (`Mechanism::fill`); this module only writes it.

use crate::{Figure, ReportError};
use enginedyn_engine::Engine;
use enginedyn_kinematics::{Model, Table};
use std::fmt::Write as _;

/// What `kinematics --out DIR` writes.
pub const KINEMATICS_FILES: [&str; 2] = ["kinematics.csv", "kinematics.svg"];

/// `kinematics.csv`'s header.
const HEADER: &str =
    "crank_deg,coef_a,coef_b,coef_c,piston_x_m,piston_v_m_s,piston_a_m_s2,rod_angle_deg";

/// `kinematics.csv` (and `kinematics --csv`): one row per angle of `t`
/// (every `step_deg` from 0), the coefficients per crank radius `r` (m) and
/// the motion at `omega` (rad/s), SI units.
pub fn kinematics_csv(t: &Table, step_deg: f64, r: f64, omega: f64) -> String {
    let mut s = String::from(HEADER);
    s.push('\n');
    for k in 0..t.x.len() {
        let cells = [
            (k as f64 * step_deg * 1e9).round() / 1e9,
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
}

/// The printed table as the seeds print it: a line naming the engine, the
/// model, R, λ and the speed, then one aligned row per angle of `t` (every
/// `step_deg` from 0), displacements in mm.
pub fn kinematics_table(
    engine: &Engine,
    model: Model,
    rpm: f64,
    omega: f64,
    t: &Table,
    step_deg: f64,
) -> String {
    let mech = engine.mechanism();
    let r = mech.r();
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
    for k in 0..t.x.len() {
        let _ = writeln!(
            text,
            "{:>8.1} {:>9.4} {:>9.4} {:>9.4} {:>10.3} {:>9.3} {:>11.1} {:>9.3}",
            k as f64 * step_deg,
            t.x[k] / r,
            t.dx[k] / r,
            t.d2x[k] / r,
            t.x[k] * 1e3,
            t.dx[k] * omega,
            t.d2x[k] * omega * omega,
            t.beta[k].to_degrees()
        );
    }
    text
}

/// `kinematics.svg`: the piston motion of `t` (every `step_deg` from 0).
pub fn kinematics_svg(
    engine: &Engine,
    model: Model,
    rpm: f64,
    t: &Table,
    step_deg: f64,
) -> Result<String, ReportError> {
    let chart = crate::kinematics_chart(
        format!(
            "{} — piston motion ({}), {rpm:.0} rpm",
            engine.name(),
            model.name()
        ),
        t,
        engine.mechanism().r(),
        step_deg,
    );
    Figure::single(KINEMATICS_FILES[1], chart).render()
}
