//! `enginedyn template`: prints a commented engine file that runs as it is
//! with the bundled diagram (the text is `enginedyn_engine::template`'s).

use crate::Failure;
use crate::args::{CombustionArg, TemplateArgs, TemplateLayoutArg};
use enginedyn_engine::template::{CombustionKind, TemplateLayout, TemplateOptions, template};

/// Prints the template on standard output (exit 2 for a cylinder count
/// the layout cannot have).
pub fn run(a: &TemplateArgs) -> Result<(), Failure> {
    let layout = match a.layout {
        TemplateLayoutArg::Inline => TemplateLayout::Inline,
        TemplateLayoutArg::Vee => TemplateLayout::Vee,
        TemplateLayoutArg::Boxer => TemplateLayout::Boxer,
    };
    let combustion = a.combustion.combustion.map(|c| match c {
        CombustionArg::Petrol => CombustionKind::Petrol,
        CombustionArg::Diesel => CombustionKind::Diesel,
    });
    let text = template(&TemplateOptions {
        cylinders: usize::from(a.cylinders),
        layout,
        torsion: a.torsion,
        combustion,
    })
    .map_err(|e| Failure::usage(e.to_string()))?;
    crate::emit(&text);
    Ok(())
}
