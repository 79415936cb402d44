//! p–V data to p–φ: split the loop into strokes at the volume's extremes and
//! place each point on the crank angle that gives its volume on its own
//! stroke (seed 003's graphical construction, done with the exact volume law).

use crate::{IngestError, Trace};
use enginedyn_kinematics::Cylinder;
use std::f64::consts::PI;

/// A reversal is taken as real once the volume has come back this share of
/// the swept volume from its extreme (digitising noise stays below it).
const REVERSAL: f64 = 0.02;
/// Points may lie this share of the swept volume outside the cylinder
/// (digitising and rounding); they are clamped. Further out is an error.
const OUTSIDE: f64 = 0.01;
/// Volume error for the conditioning warning: 0.1 % of the swept volume.
const VOLUME_ERROR: f64 = 1e-3;

/// Converts a p–V trace (volumes in m³ in `angle_deg`) to cycle angles (deg).
/// `line` is the trace's first line, for messages.
pub(crate) fn to_angles(
    tr: Trace,
    cyl: &Cylinder,
    cycle_deg: f64,
    start_bdc: bool,
    line: usize,
    notes: &mut Vec<String>,
) -> Result<Trace, IngestError> {
    let mech = cyl.mechanism();
    let stroke = mech.stroke();
    let area = cyl.piston_area();
    let vc = cyl.clearance_volume();
    let vd = cyl.swept_volume();
    let strokes = if cycle_deg > 400.0 { 4 } else { 2 };
    let mut x = Vec::with_capacity(tr.angle_deg.len());
    for (k, v) in tr.angle_deg.iter().enumerate() {
        let xi = (v - vc) / area;
        if xi < -OUTSIDE * stroke || xi > stroke * (1.0 + OUTSIDE) {
            return Err(IngestError::Data(format!(
                "p–V point {} of the trace starting on line {line}: volume {:.6e} m³ lies outside the cylinder [{:.6e}, {:.6e}] m³ (check the volume unit and the compression ratio)",
                k + 1,
                v,
                vc,
                vc + vd
            )));
        }
        x.push(xi.clamp(0.0, stroke));
    }
    // Stroke boundaries at the extremes: down-strokes raise x, up-strokes lower it.
    let mut down = !start_bdc;
    let mut boundaries = Vec::new();
    let (mut ext, mut ext_i) = (x[0], 0usize);
    for (i, &xi) in x.iter().enumerate().skip(1) {
        let beyond = if down { xi > ext } else { xi < ext };
        if beyond {
            ext = xi;
            ext_i = i;
        } else if (ext - xi).abs() > REVERSAL * stroke {
            boundaries.push(ext_i);
            down = !down;
            ext = xi;
            ext_i = i;
        }
    }
    if boundaries.len() >= strokes {
        return Err(IngestError::Data(format!(
            "p–V trace starting on line {line}: the volume reverses {} times, more than the {} strokes of a cycle (is it one cycle, in cycle order?)",
            boundaries.len(),
            strokes
        )));
    }
    let mut angles = Vec::with_capacity(x.len());
    let mut s = 0usize;
    let mut worst: f64 = 0.0;
    let mut crowded = 0usize;
    for (i, &xi) in x.iter().enumerate() {
        while s < boundaries.len() && i > boundaries[s] {
            s += 1;
        }
        // Stroke s from the start: down-strokes are even from TDC, odd from BDC.
        let is_down = s.is_multiple_of(2) != start_bdc;
        let base = if start_bdc {
            2.0 * PI * s.div_ceil(2) as f64 - 2.0 * PI
        } else {
            2.0 * PI * (s / 2) as f64
        };
        let phi = mech
            .angle_at(xi, is_down)
            .map_err(|e| IngestError::Data(format!("p–V trace starting on line {line}: {e}")))?;
        let a = phi + base;
        // Conditioning: crank-angle error of a 0.1 % volume error here.
        let dv = cyl.dvolume(phi).abs();
        let err = if dv > 0.0 {
            (VOLUME_ERROR * vd / dv).to_degrees()
        } else {
            f64::INFINITY
        };
        if err > 1.0 {
            crowded += 1;
            // Distance from the nearer dead centre (deg).
            let bdc = mech.bdc_after_tdc();
            let d = phi.min((phi - bdc).abs()).min(2.0 * PI - phi).to_degrees();
            worst = worst.max(d);
        }
        angles.push(a.to_degrees());
    }
    // Points on the extremes of neighbouring strokes may coincide: keep the first.
    let mut order: Vec<usize> = (0..angles.len()).collect();
    order.sort_by(|&a, &b| angles[a].total_cmp(&angles[b]));
    let mut out = Trace {
        cycle: tr.cycle,
        cylinder: tr.cylinder,
        angle_deg: Vec::with_capacity(angles.len()),
        values: Vec::with_capacity(angles.len()),
        rpm: tr.rpm,
    };
    for i in order {
        if out.angle_deg.last().is_some_and(|&l| angles[i] - l < 1e-6) {
            continue;
        }
        out.angle_deg.push(angles[i]);
        out.values.push(tr.values[i]);
    }
    if crowded > 0 {
        let note = format!(
            "p–V inversion: {crowded} points lie within {worst:.1}° of TDC or BDC, where a 0.1 % volume error moves the crank angle by more than 1°: their pressure is placed less surely"
        );
        if !notes.contains(&note) {
            notes.push(note);
        }
    }
    Ok(out)
}
