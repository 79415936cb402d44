//! A speed × load map (`enginedyn sweep --rpm A:B:S --imep X:Y:Z`, an
//! engine file with `[combustion]`): at each load the design cycle is
//! synthesised once (the lossless cycle is the same at every speed) and
//! analysed at every speed; one flywheel for the whole map, sized at the
//! point that needs the most inertia, which is named.

use crate::diagram::load_diagram;
use crate::error::Result;
use crate::session::Session;
use crate::synth::{NOTE_PREFIX, synthesise};
use enginedyn_numerics::format::human;
use enginedyn_pipeline::Point;
use rayon::prelude::*;

/// One point of a map.
#[derive(Debug)]
pub struct MapPoint {
    /// The IMEP asked for (bar).
    pub imep_target_bar: f64,
    /// Its load's place in [`SweepMap::loads`] and [`SweepMap::diagrams`].
    pub load: usize,
    /// What the map keeps of the analysis at this speed and load (its
    /// summary), the map's flywheel on it.
    pub point: Point,
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
    /// The loads (bar).
    pub loads: Vec<f64>,
    /// The speeds (rpm).
    pub rpms: Vec<f64>,
    /// The point the flywheel was sized at: (rpm, IMEP target in bar), when
    /// one was sized.
    pub sized_at: Option<(f64, f64)>,
    /// The diagram synthesised at each load.
    pub diagrams: Vec<MapLoad>,
    /// What the map says once: how the diagrams were made, where the
    /// flywheel was sized.
    pub notes: Vec<String>,
}

impl SweepMap {
    /// The diagram each point ran on, in the order of [`Self::points`].
    pub fn diagrams_for_points(&self) -> Vec<&MapLoad> {
        self.points.iter().map(|p| &self.diagrams[p.load]).collect()
    }
}

impl Session {
    /// One load of a map: its diagram synthesised and put on the grid, then
    /// analysed at every speed, each analysis kept as its [`Point`].
    fn map_load(&self, rpms: &[f64], imep: f64) -> Result<(MapLoad, Vec<Point>)> {
        let d = synthesise(&self.loaded, None, Some(imep), self.method.step())?;
        let grid = load_diagram(d.input(), &self.parse, &self.grid)?;
        let design = d.design_summary();
        let points = rpms
            .par_iter()
            .map(|&rpm| {
                enginedyn_pipeline::analyse_with(
                    self.tables(),
                    self.engine(),
                    &grid,
                    rpm,
                    &self.opts,
                )
                .map(|mut a| {
                    a.summary.design = Some(design);
                    a.summary.notes.extend(d.warnings.iter().cloned());
                    Point::of(a)
                })
                .map_err(|e| crate::Error::usage(e.to_string()))
            })
            .collect::<Result<Vec<_>>>()?;
        let load = MapLoad {
            inputs: crate::inputs::of(&self.loaded, &[d.input()])?,
            name: d.name,
            heat_released_j: d.heat_released_j,
        };
        Ok((load, points))
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
        loads: &[f64],
        shown: &str,
        shown_loads: &str,
    ) -> Result<SweepMap> {
        crate::options::check_map_size(rpms.len(), loads.len(), shown, shown_loads)?;
        let engine = self.engine();
        // Every load runs; the first failure in the order of --imep is said.
        let ran: Vec<Result<(MapLoad, Vec<Point>)>> = loads
            .par_iter()
            .map(|&imep| self.map_load(rpms, imep))
            .collect();
        let mut diagrams = Vec::with_capacity(loads.len());
        let mut points = Vec::with_capacity(loads.len() * rpms.len());
        for (l, r) in ran.into_iter().enumerate() {
            let (d, ps) = r?;
            diagrams.push(d);
            points.extend(ps.into_iter().map(|point| MapPoint {
                imep_target_bar: loads[l],
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
        let part = worst.and_then(|(k, _)| points[k].point.flywheel.clone());
        let sized_at = worst.map(|(k, _)| (points[k].point.summary.rpm, points[k].imep_target_bar));
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
        let mut notes = Vec::new();
        if let (Some(first), Some(last)) = (diagrams.first(), diagrams.last()) {
            notes.push(format!(
                "{NOTE_PREFIX} of {} at each load of --imep {shown_loads} (heat released {} to {} J per cylinder): the lossless cycle is the same at every speed",
                self.loaded.shown(),
                human(first.heat_released_j),
                human(last.heat_released_j)
            ));
        }
        if let (Some((rpm, imep)), Some(part)) = (sized_at, &part) {
            notes.push(format!(
                "flywheel sized once at {} rpm and IMEP {} bar, the point of the map that needs the most inertia ({} kg m²): the same part at every point; speed_fluctuation_achieved is the δ it gives there",
                human(rpm),
                human(imep),
                human(part.required_inertia)
            ));
        }
        Ok(SweepMap {
            points,
            loads: loads.to_vec(),
            rpms: rpms.to_vec(),
            sized_at,
            diagrams,
            notes,
        })
    }
}
