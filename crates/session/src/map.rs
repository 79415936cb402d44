//! A speed × load map (`enginedyn sweep --rpm A:B:S --imep X:Y:Z`, an
//! engine file with `[combustion]`): at each load the design cycle is
//! synthesised once (the lossless cycle is the same at every speed) and
//! analysed at every speed; one flywheel for the whole map, sized at the
//! point that needs the most inertia, which is named.

use crate::diagram::load_diagram;
use crate::error::Result;
use crate::session::Session;
use crate::synth::{NOTE_PREFIX, Synthesised, synthesise};
use enginedyn_numerics::format::human;
use enginedyn_pipeline::Analysis;
use rayon::prelude::*;

/// One point of a map.
#[derive(Debug)]
pub struct MapPoint {
    /// The IMEP asked for (bar).
    pub imep_target_bar: f64,
    /// Its load's place in [`SweepMap::loads`] and [`SweepMap::diagrams`].
    pub load: usize,
    /// The analysis at this speed and load, the map's flywheel on it.
    pub analysis: Analysis,
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
    pub diagrams: Vec<Synthesised>,
    /// What the map says once: how the diagrams were made, where the
    /// flywheel was sized.
    pub notes: Vec<String>,
}

impl SweepMap {
    /// The diagram each point ran on, in the order of [`Self::points`].
    pub fn diagrams_for_points(&self) -> Vec<&Synthesised> {
        self.points.iter().map(|p| &self.diagrams[p.load]).collect()
    }
}

impl Session {
    /// The analyses at every speed of `rpms` and load of `loads` (IMEP
    /// targets, bar) of the engine file's `[combustion]`; `shown` names
    /// the speeds given (`1000:3000:500`) and `shown_loads` the loads.
    pub fn sweep_map(
        &self,
        rpms: &[f64],
        loads: &[f64],
        shown: &str,
        shown_loads: &str,
    ) -> Result<SweepMap> {
        let engine = self.engine();
        let step = self.method.step();
        let diagrams: Vec<Synthesised> = loads
            .par_iter()
            .map(|&imep| synthesise(&self.loaded, None, Some(imep), step))
            .collect::<Result<_>>()?;
        let grids = diagrams
            .par_iter()
            .map(|d| load_diagram(d.input(), &self.parse, &self.grid))
            .collect::<Result<Vec<_>>>()?;
        let pairs: Vec<(usize, f64)> = (0..loads.len())
            .flat_map(|l| rpms.iter().map(move |&r| (l, r)))
            .collect();
        let mut analyses: Vec<Analysis> = pairs
            .par_iter()
            .map(|&(l, rpm)| {
                enginedyn_pipeline::analyse_with(self.tables(), engine, &grids[l], rpm, &self.opts)
                    .map_err(|e| crate::Error::usage(e.to_string()))
            })
            .collect::<Result<_>>()?;
        // The point that needs the most inertia sizes the one flywheel.
        let worst = analyses
            .iter()
            .enumerate()
            .filter_map(|(k, an)| an.flywheel.as_ref().map(|f| (k, f.required_inertia)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let part = worst.and_then(|(k, _)| analyses[k].flywheel.clone());
        let sized_at = worst.map(|(k, _)| (pairs[k].1, loads[pairs[k].0]));
        let file_rpm = engine.operating().rpm;
        for an in &mut analyses {
            if let Some(part) = &part {
                enginedyn_pipeline::with_flywheel(an, part);
            }
            let rpm = an.summary.rpm;
            if file_rpm.is_none_or(|f| f.to_bits() != rpm.to_bits()) {
                an.summary
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
        let points = pairs
            .iter()
            .zip(analyses)
            .map(|(&(l, _), analysis)| MapPoint {
                imep_target_bar: loads[l],
                load: l,
                analysis,
            })
            .collect();
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
