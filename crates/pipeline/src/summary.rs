//! The summary figures of one operating point, in INTERFACE.md's key order.

/// Summary figures (SI units as named by each key). `None` is JSON `null`.
#[derive(Debug, Clone, PartialEq)]
#[allow(missing_docs)] // each field is the summary.json key of the same name (INTERFACE.md)
pub struct Summary {
    pub rpm: f64,
    pub omega_rad_s: f64,
    pub imep_bar: Option<f64>,
    pub indicated_work_per_cylinder_j: Option<f64>,
    pub mean_torque_nm: Option<f64>,
    pub power_kw: Option<f64>,
    pub torque_max_nm: Option<f64>,
    pub torque_min_nm: Option<f64>,
    pub torque_nonuniformity: Option<f64>,
    pub excess_work_j: Option<f64>,
    pub excess_work_coefficient: Option<f64>,
    pub required_inertia_kg_m2: Option<f64>,
    pub flywheel_inertia_kg_m2: Option<f64>,
    pub flywheel_gd2_n_m2: Option<f64>,
    pub flywheel_outer_diameter_m: Option<f64>,
    pub flywheel_mass_kg: Option<f64>,
    pub flywheel_width_m: Option<f64>,
    pub speed_fluctuation_achieved: Option<f64>,
    pub stroke_m: f64,
    pub lambda: f64,
    pub piston_speed_mean_m_s: f64,
    pub piston_speed_max_m_s: f64,
    pub piston_accel_max_m_s2: f64,
    pub piston_accel_min_m_s2: f64,
    pub gas_force_max_n: Option<f64>,
    pub side_force_max_n: Option<f64>,
    pub rod_force_max_n: Option<f64>,
    pub crankpin_load_max_n: Option<f64>,
    pub crankpin_load_mean_n: Option<f64>,
    pub journal_torque_max_nm: f64,
    pub journal_most_loaded: usize,
    pub energy_balance_error: Option<f64>,
    /// `models.kinematics`.
    pub kinematics: &'static str,
    /// `models.rod_model`.
    pub rod_model: &'static str,
    /// `models.interpolation`.
    pub interpolation: &'static str,
    /// `models.grid_step_deg`.
    pub grid_step_deg: f64,
    /// `models.integration`.
    pub integration: &'static str,
    /// Number of measured cycles, when more than one.
    pub cycles: Option<usize>,
    /// Cycle-to-cycle statistics, when several cycles were measured.
    pub cycle_stats: Option<CycleSummary>,
    /// Pegging applied to relative traces.
    pub pegging: Option<Pegging>,
    /// The TDC offset a measured p–φ trace suggests (deg).
    pub tdc_offset_estimate_deg: Option<f64>,
    /// With `--tolerance`: the largest estimated relative error of the key
    /// results for the methods chosen.
    pub estimated_relative_error: Option<f64>,
    pub notes: Vec<String>,
}

/// Cycle-to-cycle statistics (INTERFACE.md's keys of the same names).
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)]
pub struct CycleSummary {
    pub cycles: usize,
    pub imep_std_bar: Option<f64>,
    pub imep_cov: Option<f64>,
    pub p_max_mean_bar: f64,
    pub p_max_cov: f64,
    pub p_max_angle_mean_deg: f64,
    pub p_max_angle_std_deg: f64,
}

/// Pegging as `summary.json` reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pegging {
    /// `"bar"` or `"polytropic"`.
    pub method: &'static str,
    /// Mean offset added (bar).
    pub offset_bar: f64,
    /// The exponent of polytropic pegging.
    pub polytropic_n: Option<f64>,
}

/// A summary value, as the report writers need it.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A number or null.
    Num(Option<f64>),
    /// A whole number.
    Int(usize),
    /// Text.
    Text(&'static str),
    /// A nested object, in key order.
    Map(Vec<(&'static str, Value)>),
    /// A list of strings.
    List(Vec<String>),
}

impl Summary {
    /// A summary with every fixed key and nothing measured: lists the
    /// columns of `summary.csv`.
    pub fn empty() -> Self {
        Summary {
            rpm: 0.0,
            omega_rad_s: 0.0,
            imep_bar: None,
            indicated_work_per_cylinder_j: None,
            mean_torque_nm: None,
            power_kw: None,
            torque_max_nm: None,
            torque_min_nm: None,
            torque_nonuniformity: None,
            excess_work_j: None,
            excess_work_coefficient: None,
            required_inertia_kg_m2: None,
            flywheel_inertia_kg_m2: None,
            flywheel_gd2_n_m2: None,
            flywheel_outer_diameter_m: None,
            flywheel_mass_kg: None,
            flywheel_width_m: None,
            speed_fluctuation_achieved: None,
            stroke_m: 0.0,
            lambda: 0.0,
            piston_speed_mean_m_s: 0.0,
            piston_speed_max_m_s: 0.0,
            piston_accel_max_m_s2: 0.0,
            piston_accel_min_m_s2: 0.0,
            gas_force_max_n: None,
            side_force_max_n: None,
            rod_force_max_n: None,
            crankpin_load_max_n: None,
            crankpin_load_mean_n: None,
            journal_torque_max_nm: 0.0,
            journal_most_loaded: 0,
            energy_balance_error: None,
            kinematics: "",
            rod_model: "",
            interpolation: "",
            grid_step_deg: 0.0,
            integration: "",
            cycles: None,
            cycle_stats: None,
            pegging: None,
            tdc_offset_estimate_deg: None,
            estimated_relative_error: None,
            notes: Vec::new(),
        }
    }

    /// Every key in INTERFACE.md's order, then the optional keys present.
    pub fn fields(&self) -> Vec<(&'static str, Value)> {
        use Value::{Int, Num};
        let s = |v: f64| Num(Some(v));
        let mut f = vec![
            ("rpm", s(self.rpm)),
            ("omega_rad_s", s(self.omega_rad_s)),
            ("imep_bar", Num(self.imep_bar)),
            (
                "indicated_work_per_cylinder_j",
                Num(self.indicated_work_per_cylinder_j),
            ),
            ("mean_torque_nm", Num(self.mean_torque_nm)),
            ("power_kw", Num(self.power_kw)),
            ("torque_max_nm", Num(self.torque_max_nm)),
            ("torque_min_nm", Num(self.torque_min_nm)),
            ("torque_nonuniformity", Num(self.torque_nonuniformity)),
            ("excess_work_j", Num(self.excess_work_j)),
            ("excess_work_coefficient", Num(self.excess_work_coefficient)),
            ("required_inertia_kg_m2", Num(self.required_inertia_kg_m2)),
            ("flywheel_inertia_kg_m2", Num(self.flywheel_inertia_kg_m2)),
            ("flywheel_gd2_n_m2", Num(self.flywheel_gd2_n_m2)),
            (
                "flywheel_outer_diameter_m",
                Num(self.flywheel_outer_diameter_m),
            ),
            ("flywheel_mass_kg", Num(self.flywheel_mass_kg)),
            ("flywheel_width_m", Num(self.flywheel_width_m)),
            (
                "speed_fluctuation_achieved",
                Num(self.speed_fluctuation_achieved),
            ),
            ("stroke_m", s(self.stroke_m)),
            ("lambda", s(self.lambda)),
            ("piston_speed_mean_m_s", s(self.piston_speed_mean_m_s)),
            ("piston_speed_max_m_s", s(self.piston_speed_max_m_s)),
            ("piston_accel_max_m_s2", s(self.piston_accel_max_m_s2)),
            ("piston_accel_min_m_s2", s(self.piston_accel_min_m_s2)),
            ("gas_force_max_n", Num(self.gas_force_max_n)),
            ("side_force_max_n", Num(self.side_force_max_n)),
            ("rod_force_max_n", Num(self.rod_force_max_n)),
            ("crankpin_load_max_n", Num(self.crankpin_load_max_n)),
            ("crankpin_load_mean_n", Num(self.crankpin_load_mean_n)),
            ("journal_torque_max_nm", s(self.journal_torque_max_nm)),
            ("journal_most_loaded", Int(self.journal_most_loaded)),
            ("energy_balance_error", Num(self.energy_balance_error)),
            (
                "models",
                Value::Map(vec![
                    ("kinematics", Value::Text(self.kinematics)),
                    ("rod_model", Value::Text(self.rod_model)),
                    ("interpolation", Value::Text(self.interpolation)),
                    ("grid_step_deg", s(self.grid_step_deg)),
                    ("integration", Value::Text(self.integration)),
                ]),
            ),
            ("notes", Value::List(self.notes.clone())),
        ];
        if let Some(c) = self.cycles {
            f.push(("cycles", Int(c)));
        }
        if let Some(c) = &self.cycle_stats {
            f.push(("imep_std_bar", Num(c.imep_std_bar)));
            f.push(("imep_cov", Num(c.imep_cov)));
            f.push(("p_max_mean_bar", Num(Some(c.p_max_mean_bar))));
            f.push(("p_max_cov", Num(Some(c.p_max_cov))));
            f.push(("p_max_angle_mean_deg", Num(Some(c.p_max_angle_mean_deg))));
            f.push(("p_max_angle_std_deg", Num(Some(c.p_max_angle_std_deg))));
        }
        if let Some(p) = &self.pegging {
            f.push((
                "pegging",
                Value::Map(vec![
                    ("method", Value::Text(p.method)),
                    ("offset_bar", Num(Some(p.offset_bar))),
                    ("polytropic_n", Num(p.polytropic_n)),
                ]),
            ));
        }
        if let Some(t) = self.tdc_offset_estimate_deg {
            f.push(("tdc_offset_estimate_deg", Num(Some(t))));
        }
        if let Some(e) = self.estimated_relative_error {
            f.push(("estimated_relative_error", Num(Some(e))));
        }
        f
    }
}
