//! `enginedyn synth`: the diagram of an engine file's `[combustion]` burn
//! law (INTERFACE.md "Combustion"); the cycle and its text are
//! `enginedyn_session::synth`'s.

use crate::Failure;
use crate::args::SynthArgs;
use enginedyn_session::Loaded;
use enginedyn_session::options::DEFAULT_SYNTH_STEP_DEG;

/// Writes the synthesised diagram to `--out` (or standard output for `-`)
/// and says what it gives.
pub fn run(a: &SynthArgs) -> Result<(), Failure> {
    let loaded = Loaded::from_file(&a.engine)?;
    if a.out.as_os_str() != "-" {
        enginedyn_session::synth::check_out(&a.out)?;
    }
    let step = a.step.unwrap_or(DEFAULT_SYNTH_STEP_DEG);
    let s = enginedyn_session::synth::synthesise(&loaded, a.rpm, a.imep, step)?;
    if a.out.as_os_str() == "-" {
        crate::emit(&s.text);
        return Ok(());
    }
    enginedyn_session::synth::write(&s, &a.out)?;
    crate::emit(&format!(
        "wrote {}: synthetic diagram, IMEP {} bar net{}, heat released {} J per cylinder, {} rows at {}°\n",
        a.out.display(),
        crate::human((s.imep_bar * 1e4).round() / 1e4),
        if s.imep_target_bar.is_some() {
            " (the target)"
        } else {
            ""
        },
        crate::human((s.heat_released_j * 10.0).round() / 10.0),
        s.text.lines().filter(|l| !l.starts_with('#')).count() - 1,
        crate::human(step)
    ));
    Ok(())
}
