//! A speed × load map (`enginedyn sweep --rpm A:B:S --imep X:Y:Z`, or
//! `--load P:Q:R` in percent of the full-load line; an engine file with
//! `[combustion]`): at each load the design cycle is synthesised once when
//! it is the same at every speed (a fixed IMEP, no curve over speed), else
//! at each point; each is analysed at its speed. One flywheel for the whole
//! map, sized at the point that needs the most inertia, which is named;
//! the full-load row names the rated-power and peak-torque points.

use crate::diagram::load_diagram;
use crate::error::Result;
use crate::session::Session;
use crate::synth::{NOTE_PREFIX, synthesise};
use enginedyn_flywheel::Flywheel;
use enginedyn_numerics::format::human;
use enginedyn_pipeline::Point;
use rayon::prelude::*;

/// The loads of a map.
#[derive(Debug, Clone, PartialEq)]
pub enum Loads {
    /// Net IMEP targets (bar), `--imep`.
    Imep(Vec<f64>),
    /// Percent of the full-load line at each speed, `--load`.
    Percent(Vec<f64>),
}

impl Loads {
    /// The loads as given (bar or percent).
    pub fn values(&self) -> &[f64] {
        match self {
            Loads::Imep(v) | Loads::Percent(v) => v,
        }
    }

    /// The flag that gave them.
    pub fn flag(&self) -> &'static str {
        match self {
            Loads::Imep(_) => "--imep",
            Loads::Percent(_) => "--load",
        }
    }
}

/// One point of a map.
#[derive(Debug)]
pub struct MapPoint {
    /// The IMEP asked for (bar).
    pub imep_target_bar: f64,
    /// Its load in percent of the full-load line (`--load`).
    pub load_pct: Option<f64>,
    /// Its load's place in [`SweepMap::loads`] and [`SweepMap::diagrams`].
    pub load: usize,
    /// What the map keeps of the analysis at this speed and load (its
    /// summary), the map's flywheel on it.
    pub point: Point,
}

impl MapPoint {
    /// How the point's load is named: `IMEP 9 bar` or `75 % load (IMEP
    /// 9.4 bar)`.
    pub fn load_name(&self) -> String {
        match self.load_pct {
            Some(pct) => format!(
                "{} % load (IMEP {} bar)",
                human(pct),
                human((self.imep_target_bar * 1e3).round() / 1e3)
            ),
            None => format!("IMEP {} bar", human(self.imep_target_bar)),
        }
    }
}

/// What a map keeps of the diagram synthesised at one load: its name, its
/// heat released and its record (`inputs`); the diagram's text and grid
/// are dropped once the load's speeds have run.
#[derive(Debug)]
pub struct MapLoad {
    /// How messages and tables name it: `synthesised from FILE [combustion]`.
    pub name: String,
    /// The heat released per cylinder and cycle (J).
    pub heat_released_j: f64,
    /// The engine and the diagram as `summary.json`'s `inputs` gives them.
    pub inputs: enginedyn_report::Inputs,
}

/// A speed × load map's results.
#[derive(Debug)]
pub struct SweepMap {
    /// Load by load (in the order of `--imep`), speed by speed.
    pub points: Vec<MapPoint>,
    /// The loads as given.
    pub loads: Loads,
    /// The speeds (rpm).
    pub rpms: Vec<f64>,
    /// The point the flywheel was sized at: (rpm, IMEP target in bar), when
    /// one was sized.
    pub sized_at: Option<(f64, f64)>,
    /// The diagram synthesised at each load (at the first speed, when
    /// each point has its own).
    pub diagrams: Vec<MapLoad>,
    /// At the highest load: the speed of the most power and that power
    /// (kW, brake with `[friction]`, else effective).
    pub rated_power: Option<(f64, f64)>,
    /// At the highest load: the speed of the most torque and that torque
    /// (N m, brake with `[friction]`, else effective).
    pub peak_torque: Option<(f64, f64)>,
    /// What the map says once: how the diagrams were made, where the
    /// flywheel was sized.
    pub notes: Vec<String>,
}

impl SweepMap {
    /// The diagram each point ran on, in the order of [`Self::points`].
    pub fn diagrams_for_points(&self) -> Vec<&MapLoad> {
        self.points.iter().map(|p| &self.diagrams[p.load]).collect()
    }

    /// The columns a map's row adds to the summary's (INTERFACE "sweep
    /// --load"): the IMEP asked for, the load in percent of the full-load
    /// line (with `--load`), and the point the one flywheel was sized at,
    /// named apart from each point's own `required_inertia_kg_m2`.
    pub fn point_keys(&self, p: &MapPoint) -> Vec<(&'static str, f64)> {
        enginedyn_pipeline::schema::MAP_COLUMNS
            .iter()
            .zip(self.map_values(p))
            .filter_map(|(&(name, _), v)| v.map(|v| (name, v)))
            .collect()
    }

    /// The values of [`enginedyn_pipeline::schema::MAP_COLUMNS`] at `p`.
    fn map_values(&self, p: &MapPoint) -> [Option<f64>; 4] {
        [
            Some(p.imep_target_bar),
            p.load_pct,
            self.sized_at.map(|s| s.0),
            self.sized_at.map(|s| s.1),
        ]
    }

    /// The map as a Parquet table (`map/1`: the summary's columns, then
    /// [`enginedyn_pipeline::schema::MAP_COLUMNS`]), with `session`'s
    /// metadata.
    pub fn parquet(&self, session: &Session) -> Result<Vec<u8>> {
        use enginedyn_pipeline::schema::{MapRecord, SummaryRecord};
        let engine = session.engine().name();
        let rows: Vec<MapRecord<'_>> = self
            .points
            .iter()
            .map(|p| {
                let d = &self.diagrams[p.load];
                MapRecord {
                    summary: SummaryRecord {
                        file: &d.name,
                        error: None,
                        engine,
                        diagram_blake3: d.inputs.diagram_blake3.first().map(String::as_str),
                        summary: Some(&p.point.summary),
                    },
                    map: self.map_values(p),
                }
            })
            .collect();
        enginedyn_tables::map_parquet(&rows, &session.meta()?)
            .map_err(|e| crate::Error::data(e.to_string()))
    }

    /// The map as `sweep.csv` writes it: the summary's columns and
    /// [`Self::point_keys`], a row a point.
    pub fn csv(&self) -> String {
        let table: Vec<enginedyn_report::CsvRow> = self
            .points
            .iter()
            .map(|p| {
                let mut cells = enginedyn_report::flatten(&p.point.summary);
                for (k, v) in self.point_keys(p) {
                    cells.push((k.to_string(), enginedyn_numerics::format::csv(v)));
                }
                (self.diagrams[p.load].name.clone(), String::new(), cells)
            })
            .collect();
        enginedyn_report::summary_csv(&table)
    }
}

impl Session {
    /// The diagram `d` synthesised from `[combustion]` analysed at `rpm`
    /// (its samples carry no speed), with its design figures and warnings.
    pub fn analyse_synthesised(
        &self,
        d: &crate::synth::Synthesised,
        rpm: f64,
    ) -> Result<enginedyn_pipeline::Analysis> {
        let grid = load_diagram(d.input(), &self.parse, &self.grid)?;
        let mut a =
            enginedyn_pipeline::analyse_with(self.tables(), self.engine(), &grid, rpm, &self.opts)
                .map_err(|e| crate::Error::usage(e.to_string()))?;
        a.summary.design = Some(d.design_summary());
        a.summary.notes.extend(d.warnings.iter().cloned());
        Ok(a)
    }

    /// One synthesised diagram analysed at each of `rpms` (IMEP targets
    /// `targets`, bar, one a speed, or one for all): its [`MapLoad`] (the
    /// first speed's) and each speed's [`Point`].
    fn map_load(
        &self,
        rpms: &[f64],
        targets: &[f64],
        per_point: bool,
    ) -> Result<(MapLoad, Vec<Point>)> {
        let step = self.method.step();
        let analyse = |d: &crate::synth::Synthesised, rpm: f64| -> Result<Point> {
            Ok(Point::of(self.analyse_synthesised(d, rpm)?))
        };
        let (first, points) = if per_point {
            let ran: Vec<(crate::synth::Synthesised, Point)> = rpms
                .par_iter()
                .zip(targets)
                .map(|(&rpm, &imep)| {
                    let d = crate::synth::synthesise_samples(
                        &self.loaded,
                        Some(rpm),
                        Some(imep),
                        step,
                    )?;
                    let p = analyse(&d, rpm)?;
                    Ok((d, p))
                })
                .collect::<Result<Vec<_>>>()?;
            let mut ran = ran.into_iter();
            let (d0, p0) = ran
                .next()
                .ok_or_else(|| crate::Error::usage("a map without speeds".to_string()))?;
            let mut points = vec![p0];
            points.extend(ran.map(|(_, p)| p));
            (d0, points)
        } else {
            let d = synthesise(&self.loaded, None, Some(targets[0]), step)?;
            let points = rpms
                .par_iter()
                .map(|&rpm| analyse(&d, rpm))
                .collect::<Result<Vec<_>>>()?;
            (d, points)
        };
        let load = MapLoad {
            inputs: crate::inputs::of(&self.loaded, &[first.input()])?,
            name: first.name,
            heat_released_j: first.heat_released_j,
        };
        Ok((load, points))
    }

    /// The IMEP (bar) of `pct` percent of the full-load line at `rpm`: the
    /// line's IMEP, or for a BMEP line the IMEP whose BMEP (IMEP − FMEP by
    /// `[friction]` on the design cycle's peak) is it, by fixed-point
    /// iteration to 1e-9 (FMEP changes with the peak by b ≈ 0.005 of it).
    fn full_load_imep(&self, pct: f64, rpm: f64) -> Result<f64> {
        let file = self.loaded.shown();
        let spec = crate::synth::spec(&self.loaded)?;
        let Some(fl) = &spec.full_load else {
            return Err(crate::Error::usage(format!(
                "--load: {file} has no full-load line: give [combustion.full_load] (rpm and imep_bar or bmep_bar), or loads as --imep"
            )));
        };
        let target = pct / 100.0 * fl.curve.at(rpm);
        let engine = self.engine();
        match (fl.brake, engine.friction()) {
            (false, _) | (true, None) => Ok(target / 1e5),
            (true, Some(f)) => self.imep_for_bmep(f, target, rpm, &format!("--load {pct}")),
        }
    }

    /// The IMEP (bar) whose BMEP is `bmep_pa` at `rpm`: IMEP = BMEP + FMEP,
    /// FMEP by `friction` on the design cycle's own peak, by fixed-point
    /// iteration to 1e-9 (FMEP changes with the peak by b ≈ 0.005 of it).
    /// `what` names the load in errors.
    fn imep_for_bmep(
        &self,
        friction: &enginedyn_combustion::friction::ChenFlynn,
        bmep_pa: f64,
        rpm: f64,
        what: &str,
    ) -> Result<f64> {
        let file = self.loaded.shown();
        let spec = crate::synth::spec(&self.loaded)?;
        let engine = self.engine();
        let c_m = engine.mechanism().stroke() * rpm / 30.0;
        let mut imep = bmep_pa + friction.fmep_pa(0.0, c_m);
        for _ in 0..20 {
            let m = crate::synth::design_model(&file, engine, &spec, Some(imep / 1e5), Some(rpm))?;
            let d = enginedyn_synth::design(engine.cylinder(), &m)
                .map_err(|e| crate::Error::usage(format!("{what} at {} rpm: {e}", human(rpm))))?;
            let next = bmep_pa + friction.fmep_pa(d.solution.max_pressure(), c_m);
            if (next - imep).abs() <= 1e-9 * next {
                return Ok(next / 1e5);
            }
            imep = next;
        }
        Ok(imep / 1e5)
    }

    /// The idle criterion (`flywheel.idle_rpm`): the design cycle at idle
    /// speed and the load that overcomes friction (BMEP 0), its flywheel
    /// sized for `flywheel.idle_speed_fluctuation`: (rpm, IMEP in bar, the
    /// flywheel). `None` without `idle_rpm`; without `[friction]` (no idle
    /// load) a note says why.
    fn idle_point(&self, notes: &mut Vec<String>) -> Result<Option<(f64, f64, Flywheel)>> {
        let engine = self.engine();
        let Some((rpm, delta)) = engine.flywheel().idle else {
            return Ok(None);
        };
        let Some(friction) = engine.friction() else {
            notes.push(format!(
                "no idle criterion at flywheel.idle_rpm = {} rpm: its load is the IMEP that overcomes friction, and the engine file has no [friction]",
                human(rpm)
            ));
            return Ok(None);
        };
        let imep = self.imep_for_bmep(friction, 0.0, rpm, "flywheel.idle_rpm")?;
        let d = crate::synth::synthesise_samples(
            &self.loaded,
            Some(rpm),
            Some(imep),
            self.method.step(),
        )?;
        let a = self.analyse_synthesised(&d, rpm)?;
        let own = a.flywheel.as_ref().map_or(0.0, |f| f.engine_inertia);
        let spec = enginedyn_engine::FlywheelSpec {
            speed_fluctuation: delta,
            ..*engine.flywheel()
        };
        let omega = rpm * std::f64::consts::PI / 30.0;
        Ok(
            enginedyn_flywheel::analyse(&a.uniformity, &spec, omega, own)
                .ok()
                .map(|f| (rpm, imep, f)),
        )
    }

    /// The analyses at every speed of `rpms` and load of `loads` (IMEP
    /// targets, bar) of the engine file's `[combustion]`; `shown` names
    /// the speeds given (`1000:3000:500`) and `shown_loads` the loads. At
    /// most [`crate::options::MAX_MAP_POINTS`] points; each is kept as its
    /// summary only (streamed: a load's diagram and every analysis' curves
    /// are dropped as soon as they have given their figures).
    pub fn sweep_map(
        &self,
        rpms: &[f64],
        loads: &Loads,
        shown: &str,
        shown_loads: &str,
    ) -> Result<SweepMap> {
        let values = loads.values();
        crate::options::check_map_size(
            rpms.len(),
            values.len(),
            shown,
            (loads.flag(), shown_loads),
        )?;
        let engine = self.engine();
        let spec = crate::synth::spec(&self.loaded)?;
        let per_point = matches!(loads, Loads::Percent(_)) || spec.varies_with_speed();
        // Each load's IMEP at each speed.
        let targets: Vec<Vec<f64>> = values
            .par_iter()
            .map(|&l| match loads {
                Loads::Imep(_) => Ok(vec![l; rpms.len()]),
                Loads::Percent(_) => rpms.iter().map(|&r| self.full_load_imep(l, r)).collect(),
            })
            .collect::<Result<_>>()?;
        // Every load runs; the first failure in the order of the loads is said.
        let ran: Vec<Result<(MapLoad, Vec<Point>)>> = targets
            .par_iter()
            .map(|t| self.map_load(rpms, t, per_point))
            .collect();
        let mut diagrams = Vec::with_capacity(values.len());
        let mut points = Vec::with_capacity(values.len() * rpms.len());
        for (l, r) in ran.into_iter().enumerate() {
            let (d, ps) = r?;
            diagrams.push(d);
            points.extend(ps.into_iter().enumerate().map(|(k, point)| MapPoint {
                imep_target_bar: targets[l][k],
                load_pct: matches!(loads, Loads::Percent(_)).then_some(values[l]),
                load: l,
                point,
            }));
        }
        // The point that needs the most inertia sizes the one flywheel.
        let worst = points
            .iter()
            .enumerate()
            .filter_map(|(k, p)| p.point.flywheel.as_ref().map(|f| (k, f.required_inertia)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let mut part = worst.and_then(|(k, _)| points[k].point.flywheel.clone());
        let mut sized_at =
            worst.map(|(k, _)| (points[k].point.summary.rpm, points[k].imep_target_bar));
        let mut notes = Vec::new();
        let mut at_idle = false;
        if let Some((rpm, imep, idle)) = self.idle_point(&mut notes)? {
            let (_, delta) = engine.flywheel().idle.unwrap_or_default();
            notes.push(format!(
                "idle criterion: at {} rpm and IMEP {} bar (BMEP 0: the load that overcomes friction) with δ {} the engine needs {} kg m²",
                human(rpm),
                human((imep * 1e3).round() / 1e3),
                human(delta),
                human((idle.required_inertia * 1e4).round() / 1e4)
            ));
            if worst.is_none_or(|(_, j)| idle.required_inertia > j) {
                part = Some(idle);
                sized_at = Some((rpm, imep));
                at_idle = true;
            }
        }
        // The part runs at every speed of the map: its rim speed is held at
        // the highest, whatever speed sized its inertia.
        let top = rpms.iter().copied().fold(0.0, f64::max);
        let part = part.map(|p| {
            enginedyn_flywheel::for_top_speed(
                &p,
                engine.flywheel(),
                top * std::f64::consts::PI / 30.0,
            )
        });
        let file_rpm = engine.operating().rpm;
        for p in &mut points {
            if let Some(part) = &part {
                p.point.with_flywheel(part);
            }
            let rpm = p.point.summary.rpm;
            if file_rpm.is_none_or(|f| f.to_bits() != rpm.to_bits()) {
                p.point
                    .summary
                    .notes
                    .push(format!("speed {} rpm from --rpm {shown}", human(rpm)));
            }
        }
        if let (Some(first), Some(last)) = (diagrams.first(), diagrams.last()) {
            notes.push(format!(
                "{NOTE_PREFIX} of {} at each load of {} {shown_loads} (heat released {} to {} J per cylinder{}): {}",
                self.loaded.shown(),
                loads.flag(),
                human(first.heat_released_j),
                human(last.heat_released_j),
                if per_point { ", at the first speed" } else { "" },
                if per_point {
                    "each point's cycle made at its own speed and load"
                } else {
                    "the lossless cycle is the same at every speed"
                }
            ));
        }
        let (rated_power, peak_torque) = full_load_points(&points, values.len());
        if let (Some((r_p, p)), Some((r_t, t))) = (rated_power, peak_torque) {
            let brake = engine.friction().is_some();
            notes.push(format!(
                "at the highest load ({} {}): rated power {} kW at {} rpm, peak torque {} N m at {} rpm ({})",
                human(values[values.len() - 1]),
                if matches!(loads, Loads::Percent(_)) { "% of the full-load line" } else { "bar IMEP" },
                human((p * 100.0).round() / 100.0),
                human(r_p),
                human((t * 10.0).round() / 10.0),
                human(r_t),
                if brake { "brake figures, Chen–Flynn friction" } else { "effective: indicated × operating.mechanical_efficiency" }
            ));
        }
        if let (Some((rpm, imep)), Some(part)) = (sized_at, &part) {
            notes.push(format!(
                "flywheel sized once at {} rpm and IMEP {} bar, {} ({} kg m²), its outer diameter set by the rim speed at the map's highest speed, {} rpm: the same part at every point; speed_fluctuation_achieved is the δ it gives there",
                human(rpm),
                human((imep * 1e3).round() / 1e3),
                if at_idle {
                    "idle, which needs more inertia than any point of the map"
                } else {
                    "the point of the map that needs the most inertia"
                },
                human(part.required_inertia),
                human(top)
            ));
        }
        Ok(SweepMap {
            points,
            loads: loads.clone(),
            rpms: rpms.to_vec(),
            sized_at,
            diagrams,
            rated_power,
            peak_torque,
            notes,
        })
    }
}

/// A speed (rpm) and a figure there.
type SpeedValue = (f64, f64);

/// The rated-power and peak-torque points of the highest load's row (the
/// last of `loads` loads): (rpm, kW) and (rpm, N m), effective (brake with
/// `[friction]`).
fn full_load_points(points: &[MapPoint], loads: usize) -> (Option<SpeedValue>, Option<SpeedValue>) {
    let row = points
        .iter()
        .filter(|p| p.load + 1 == loads)
        .map(|p| &p.point.summary);
    let best = |get: fn(&enginedyn_pipeline::Summary) -> Option<f64>| {
        row.clone()
            .filter_map(|s| get(s).map(|v| (s.rpm, v)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
    };
    (best(|s| s.power_kw), best(|s| s.mean_torque_nm))
}
