//! Which notes may mean a wrong result (INTERFACE.md, "Standard output"):
//! on standard error a note that only says what was decided or assumed
//! (columns read, a banner skipped, a default taken) starts `note:`; one
//! that may mean a wrong result (data that look wrong, a figure that cannot
//! be trusted) starts `warning:`. The one home of that choice: every front
//! end prints notes through [`severity`].
//!
//! A note is a decision when it begins as one of [`DECIDED`] says; any
//! other note is a warning, so a new note is heard until it is listed here.
//!
//! ```
//! use enginedyn_pipeline::notes::{severity, Severity};
//! assert_eq!(severity("columns read: `CA [deg]` as crank angle (deg)"), Severity::Note);
//! assert_eq!(severity("near idle or motoring (mean torque 3 N m …)"), Severity::Warning);
//! ```

/// How a note is printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Severity {
    /// What was decided or assumed: `note:`.
    Note,
    /// What may be wrong: `warning:`.
    Warning,
}

impl Severity {
    /// The word that starts its line on standard error.
    pub fn label(self) -> &'static str {
        match self {
            Severity::Note => "note",
            Severity::Warning => "warning",
        }
    }
}

/// How the notes that say what was decided or assumed begin.
pub const DECIDED: &[&str] = &[
    // The reader: columns, banners, layouts, sheets, axes, speeds.
    "columns read",
    "skipped ",
    "read sheet ",
    "read group ",
    "speed ",
    "time record: the angle from",
    "the angle runs on over ",
    "firing TDC at the file's 360°",
    "cylinder traces ",
    "one trace per cylinder",
    "no TDC offset estimate",
    "the periodic spline overshoots",
    "--despike replaced ",
    // The engine file's defaults and estimates.
    "cylinder_spacing_mm not given",
    "defaults taken",
    "torsion.flywheel_inertia_kg_m2 not given",
    "torsion.flywheel_stiffness_nm_rad not given",
    "torsion.throw_inertia_kg_m2 estimated",
    "journal stiffness from journal_diameter_mm",
    // The torsion model's assumptions and what it leaves out.
    "each throw carries the reciprocating mass's mean inertia",
    "flywheel sized ",
    "pin offset: series4 and series6",
    // Methods chosen (--tolerance, accuracy) and what a spread is over.
    "--tolerance",
    "interpolation and grid-step errors against",
    "imep_std_bar, imep_cov",
    // The combustion analysis: a cycle that does not burn (motored, a fuel cut).
    "no combustion in ",
    // Knock the data cannot resolve (their sampling): null, said once.
    "knock not measured",
    // batch over folders (one file, or several).
    "1 file of another kind passed over",
    // A campaign's list: a file named twice (by any path); --replace.
    "1 file named more than once",
    "parts of another campaign removed (--replace)",
    // Synthesis for design: the diagram made from [combustion].
    "diagram synthesised from [combustion]",
];

/// Whether `note` only says what was decided or assumed.
pub fn severity(note: &str) -> Severity {
    let decided = DECIDED.iter().any(|d| note.starts_with(d))
        // "4 pressure columns: one cycle per column", "3 files of other kinds …"
        || note
            .split_once(' ')
            .is_some_and(|(n, rest)| {
                n.bytes().all(|b| b.is_ascii_digit())
                    && (rest.starts_with("pressure columns")
                        || rest.starts_with("files of other kinds")
                        || rest.starts_with("files named more than once")
                        || rest.starts_with("cycles one after another"))
            })
        // "the rigid rod, not the engine file's two-mass": a method --tolerance chose.
        || (note.starts_with("the ") && note.contains(" rod, not the engine file's"))
        || note.contains(" kinematics, not exact (the default)")
        || note.contains(": a side table, left out")
        // Torsion: a resonance without a peak of its own, orders not computed.
        || note.contains(" resonances have no peak near their crossing")
        || note.contains(" in the speed range: those orders are not computed");
    if decided {
        Severity::Note
    } else {
        Severity::Warning
    }
}

/// Each note once, in order, with its severity: what a front end prints.
pub fn printed<'a>(notes: impl IntoIterator<Item = &'a String>) -> Vec<(Severity, &'a str)> {
    let mut seen: Vec<&str> = Vec::new();
    let mut out = Vec::new();
    for n in notes {
        if !seen.contains(&n.as_str()) {
            seen.push(n);
            out.push((severity(n), n.as_str()));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decisions_are_notes_and_the_rest_warnings() {
        for n in [
            "4 pressure columns, one per cylinder (their names say which)",
            "speed 4900 rpm from the banner on line 1",
            "skipped 1 line above the header (a title or banner: `x`)",
            "no TDC offset estimate: the estimate needs a motored or fuel-cut cycle",
            "the rigid rod, not the engine file's two-mass",
            "series4 kinematics, not exact (the default): within 1e-3",
            "--tolerance 0.001: grid 0.9375° (estimated 0.00023 from the step before)",
        ] {
            assert_eq!(severity(n), Severity::Note, "{n}");
        }
        for n in [
            "near idle or motoring",
            "the banner on line 1 gives the speed `4,9`, which is not a number: not used",
            "bore_mm = 0.086: metres?",
            "a new note nobody listed",
        ] {
            assert_eq!(severity(n), Severity::Warning, "{n}");
        }
    }

    #[test]
    fn each_note_is_printed_once() {
        let notes: Vec<String> = ["a", "b", "a"].iter().map(|s| s.to_string()).collect();
        assert_eq!(printed(&notes).len(), 2);
    }
}
