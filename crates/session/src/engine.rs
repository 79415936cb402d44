//! An engine as a session holds it: the checked [`Engine`], the engine
//! file's text (for the studies that read more of it, and for a Python
//! session to pickle) and where it came from.

use crate::error::{Error, Result};
use enginedyn_engine::Engine;
use std::path::{Path, PathBuf};

/// A bundled example: the engine file and its diagram, compiled in.
#[derive(Debug, Clone, Copy)]
pub struct Bundled {
    /// Its name (the engine file's stem in `data/`).
    pub name: &'static str,
    /// The engine file's text.
    pub engine: &'static str,
    /// The diagram file's text.
    pub diagram: &'static str,
}

macro_rules! bundled {
    ($($name:literal),*) => {
        /// Every bundled example, by name (`data/NAME.toml`, `data/NAME.csv`).
        pub const BUNDLED: &[Bundled] = &[$(Bundled {
            name: $name,
            engine: include_str!(concat!("../../../data/", $name, ".toml")),
            diagram: include_str!(concat!("../../../data/", $name, ".csv")),
        }),*];
    };
}
bundled!(
    "vaz2108",
    "single",
    "i3_two_stroke",
    "i6_diesel",
    "v6_90",
    "v8_crossplane",
    "v12_60",
    "scotch_yoke"
);

/// The example `enginedyn run` runs without arguments.
pub const EXAMPLE: &Bundled = &BUNDLED[0];

impl Bundled {
    /// How messages name its engine file: `data/vaz2108.toml (bundled)`.
    pub fn engine_name(&self) -> String {
        format!("data/{}.toml (bundled)", self.name)
    }
    /// How messages name its diagram: `data/vaz2108.csv (bundled)`.
    pub fn diagram_name(&self) -> String {
        format!("data/{}.csv (bundled)", self.name)
    }
    /// The bundled example called `name`.
    pub fn find(name: &str) -> Result<&'static Bundled> {
        BUNDLED.iter().find(|b| b.name == name).ok_or_else(|| {
            Error::usage(format!(
                "no bundled engine `{}`: the bundled ones are {}",
                enginedyn_numerics::format::quote(name),
                BUNDLED
                    .iter()
                    .map(|b| b.name)
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })
    }
}

/// Where the engine came from: a file, text, or a bundled example.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The checked engine.
    pub engine: Engine,
    /// The engine file, when it came from one.
    pub path: Option<PathBuf>,
    /// The engine file's text.
    pub text: String,
    /// The bundled example it is, if it is one.
    pub bundled: Option<&'static Bundled>,
}

impl Loaded {
    /// Reads and checks the engine file at `path` (`diagram` resolved
    /// against its folder).
    pub fn from_file(path: &Path) -> Result<Self> {
        let text = enginedyn_engine::file::read_text(path)
            .map_err(|e| Error::from(e).in_file(path.display()))?;
        Self::from_text(text, Some(path))
    }

    /// Checks engine-file `text`; `path`, when given, is where it was read
    /// from (its stem the default name, `diagram` relative to its folder).
    pub fn from_text(text: String, path: Option<&Path>) -> Result<Self> {
        enginedyn_engine::file::check_len(&text).map_err(|e| match path {
            Some(p) => Error::from(e).in_file(p.display()),
            None => Error::from(e),
        })?;
        let engine = match path {
            Some(p) => enginedyn_engine::file::parse_file(&text, p)
                .map_err(|e| Error::from(e).in_file(p.display()))?,
            None => enginedyn_engine::file::parse(&text, "engine")?,
        };
        Ok(Self {
            engine,
            path: path.map(Path::to_path_buf),
            text,
            bundled: None,
        })
    }

    /// A bundled example.
    pub fn bundled(b: &'static Bundled) -> Result<Self> {
        let engine = enginedyn_engine::file::parse(b.engine, b.name)
            .map_err(|e| Error::usage(format!("{}: {e}", b.engine_name())))?;
        Ok(Self {
            engine,
            path: None,
            text: b.engine.to_string(),
            bundled: Some(b),
        })
    }

    /// The engine file `path`, or the bundled example without one.
    pub fn load(path: Option<&Path>) -> Result<Self> {
        match path {
            Some(p) => Self::from_file(p),
            None => Self::bundled(EXAMPLE),
        }
    }

    /// How messages name the engine file.
    pub fn shown(&self) -> String {
        match (&self.path, self.bundled) {
            (Some(p), _) => p.display().to_string(),
            (None, Some(b)) => b.engine_name(),
            (None, None) => "the engine file".to_string(),
        }
    }
}
