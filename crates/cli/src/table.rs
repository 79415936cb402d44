//! The readable summary table printed by `run`.

use enginedyn_engine::Engine;
use enginedyn_pipeline::Summary;
use std::fmt::Write as _;

fn row(out: &mut String, label: &str, value: Option<f64>, unit: &str, digits: usize) {
    let v = match value {
        Some(x) => format!("{x:.digits$}"),
        None => "—".to_string(),
    };
    let _ = writeln!(out, "  {label:<34} {v:>14} {unit}");
}

/// The summary as an aligned table, grouped as an engineer reads it.
pub fn summary_table(engine: &Engine, diagram: &str, s: &Summary) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "{} — {} {} {}-cylinder, {:.0} rpm",
        engine.name(),
        engine.stroke_kind().name(),
        engine.layout().name(),
        engine.cylinders(),
        s.rpm
    );
    let _ = writeln!(o, "diagram: {diagram}");
    let _ = writeln!(
        o,
        "models: kinematics {}, rod {}, interpolation {}, step {}°, integration {}",
        s.kinematics, s.rod_model, s.interpolation, s.grid_step_deg, s.integration
    );
    let _ = writeln!(o, "\nWork and torque");
    row(&mut o, "IMEP", s.imep_bar, "bar", 3);
    row(
        &mut o,
        "indicated work per cylinder",
        s.indicated_work_per_cylinder_j,
        "J",
        2,
    );
    row(&mut o, "mean torque", s.mean_torque_nm, "N m", 2);
    row(&mut o, "power", s.power_kw, "kW", 2);
    row(&mut o, "torque max", s.torque_max_nm, "N m", 1);
    row(&mut o, "torque min", s.torque_min_nm, "N m", 1);
    row(
        &mut o,
        "torque non-uniformity μ",
        s.torque_nonuniformity,
        "",
        3,
    );
    row(
        &mut o,
        "energy balance error",
        s.energy_balance_error,
        "",
        10,
    );
    let _ = writeln!(o, "\nFlywheel");
    row(&mut o, "excess work ΔE", s.excess_work_j, "J", 2);
    row(
        &mut o,
        "excess work coefficient ψ",
        s.excess_work_coefficient,
        "",
        4,
    );
    row(
        &mut o,
        "required inertia I₀",
        s.required_inertia_kg_m2,
        "kg m²",
        5,
    );
    row(
        &mut o,
        "flywheel inertia I_f",
        s.flywheel_inertia_kg_m2,
        "kg m²",
        5,
    );
    row(&mut o, "flywheel GD²", s.flywheel_gd2_n_m2, "N m²", 3);
    row(
        &mut o,
        "flywheel outer diameter",
        s.flywheel_outer_diameter_m.map(|d| d * 1e3),
        "mm",
        1,
    );
    row(
        &mut o,
        "flywheel width",
        s.flywheel_width_m.map(|d| d * 1e3),
        "mm",
        1,
    );
    row(&mut o, "flywheel mass", s.flywheel_mass_kg, "kg", 2);
    row(
        &mut o,
        "speed fluctuation achieved δ",
        s.speed_fluctuation_achieved,
        "",
        5,
    );
    let _ = writeln!(o, "\nKinematics");
    row(&mut o, "stroke", Some(s.stroke_m * 1e3), "mm", 3);
    row(&mut o, "λ = R/L", Some(s.lambda), "", 4);
    row(
        &mut o,
        "mean piston speed",
        Some(s.piston_speed_mean_m_s),
        "m/s",
        2,
    );
    row(
        &mut o,
        "max piston speed",
        Some(s.piston_speed_max_m_s),
        "m/s",
        2,
    );
    row(
        &mut o,
        "max piston acceleration",
        Some(s.piston_accel_max_m_s2),
        "m/s²",
        0,
    );
    row(
        &mut o,
        "min piston acceleration",
        Some(s.piston_accel_min_m_s2),
        "m/s²",
        0,
    );
    let _ = writeln!(o, "\nForces (largest magnitude)");
    row(&mut o, "gas force", s.gas_force_max_n, "N", 0);
    row(&mut o, "side thrust", s.side_force_max_n, "N", 0);
    row(&mut o, "rod force", s.rod_force_max_n, "N", 0);
    row(&mut o, "crank-pin load max", s.crankpin_load_max_n, "N", 0);
    row(
        &mut o,
        "crank-pin load mean",
        s.crankpin_load_mean_n,
        "N",
        0,
    );
    row(
        &mut o,
        "main-journal torque max",
        Some(s.journal_torque_max_nm),
        "N m",
        1,
    );
    let _ = writeln!(
        o,
        "  {:<34} {:>14}",
        "most loaded journal (after throw)", s.journal_most_loaded
    );
    o
}
