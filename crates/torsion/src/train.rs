//! A crankshaft laid out as a chain, from the free end.

use crate::{Chain, TorsionError, check};

/// A tuned torsional damper: a ring of `inertia` on the front mass through
/// a spring `stiffness` with a viscous `damping` across it (a viscous
/// damper has stiffness near 0 and is best given a small one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damper {
    /// Ring inertia (kg m²).
    pub inertia: f64,
    /// Spring between ring and hub (N m/rad).
    pub stiffness: f64,
    /// Viscous damping between ring and hub (N m s/rad).
    pub damping: f64,
}

/// A crankshaft and what it drives, from the free end (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct CrankTrain {
    /// Front mass (pulley, damper hub) and its spring to throw 1.
    pub front: Option<(f64, f64)>,
    /// Each throw's inertia about the crank axis.
    pub throws: Vec<f64>,
    /// Spring between throw `k` and throw `k + 1` (one fewer than throws).
    pub journals: Vec<f64>,
    /// Flywheel inertia and its spring to the last throw.
    pub flywheel: (f64, f64),
    /// Driven load inertia and its coupling's stiffness to the flywheel.
    pub load: Option<(f64, f64)>,
    /// Tuned damper on the free-end mass (the front mass, else throw 1).
    pub damper: Option<Damper>,
    /// Modal damping ratio of every mode.
    pub damping_ratio: f64,
}

/// A section of the crank train: one spring of the chain.
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    /// "front–throw 1", "throw 1–throw 2", "throw 6–flywheel", "flywheel–load".
    pub name: String,
    /// The spring's index in the chain (0-based).
    pub spring: usize,
}

/// Where the crank train's parts sit in its [`Chain`].
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// Each mass's name ("damper ring", "front", "throw 1", …, "flywheel", "load").
    pub names: Vec<String>,
    /// The free end: the front mass, else throw 1 (the damper ring is not
    /// it: it comes first in the chain, index 0, when there is one). The
    /// mode shapes of `modes.csv` are normalised to this mass (= 1).
    pub free_end: usize,
    /// Mass index of each throw.
    pub throws: Vec<usize>,
    /// Mass index of the flywheel.
    pub flywheel: usize,
    /// The crankshaft's sections from the free end (the damper's spring is
    /// not one).
    pub sections: Vec<Section>,
}

impl CrankTrain {
    /// The chain and its layout.
    ///
    /// # Errors
    ///
    /// [`TorsionError::Shape`] for no throws or a journal count other than
    /// throws − 1; [`TorsionError::Invalid`] for a value out of range.
    pub fn chain(&self) -> Result<(Chain, Layout), TorsionError> {
        let t = self.throws.len();
        if t == 0 {
            return Err(TorsionError::Shape {
                what: "throws",
                got: 0,
                need: 1,
            });
        }
        if self.journals.len() != t - 1 {
            return Err(TorsionError::Shape {
                what: "journal stiffnesses",
                got: self.journals.len(),
                need: t - 1,
            });
        }
        let mut names = Vec::new();
        let mut inertia = Vec::new();
        let mut springs = Vec::new();
        let mut ring_damping = None;
        if let Some(d) = self.damper {
            check(
                || "damper damping".into(),
                d.damping,
                d.damping >= 0.0,
                "0 or more N m s/rad",
            )?;
            names.push("damper ring".to_string());
            inertia.push(d.inertia);
            springs.push(d.stiffness);
            ring_damping = Some(d.damping);
        }
        let free_end = names.len();
        if let Some((j, k)) = self.front {
            names.push("front".to_string());
            inertia.push(j);
            springs.push(k);
        }
        let mut throws = Vec::with_capacity(t);
        for (k, &j) in self.throws.iter().enumerate() {
            throws.push(names.len());
            names.push(format!("throw {}", k + 1));
            inertia.push(j);
            springs.push(if k + 1 < t {
                self.journals[k]
            } else {
                self.flywheel.1
            });
        }
        let flywheel = names.len();
        names.push("flywheel".to_string());
        inertia.push(self.flywheel.0);
        if let Some((j, k)) = self.load {
            springs.push(k);
            names.push("load".to_string());
            inertia.push(j);
        }
        let first = usize::from(self.damper.is_some());
        let sections = (first..springs.len())
            .map(|s| Section {
                name: format!("{}–{}", names[s], names[s + 1]),
                spring: s,
            })
            .collect();
        let mut chain = Chain::new(inertia, springs)?.with_damping_ratio(self.damping_ratio)?;
        if let Some(c) = ring_damping {
            chain = chain.with_spring_damping(0, c)?;
        }
        Ok((
            chain,
            Layout {
                names,
                free_end,
                throws,
                flywheel,
                sections,
            },
        ))
    }
}
