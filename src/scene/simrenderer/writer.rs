//! What both scene writers ([`super::to_toml`], [`super::to_simrenderer`]) build as they go:
//! the text, what the format refuses and what will not read back to the bit. Each format
//! adds its own sections in an `impl Writer<ItsFormat>` of its module.

use super::exact;
use super::{Refused, Written};
use glam::DVec3;
use std::marker::PhantomData;

/// A scene file format's name (as [`Refused`] gives it) and how it writes a vector.
pub(super) trait Format {
    const NAME: &'static str;
    fn vec3(v: DVec3) -> String;
}

pub(super) struct Writer<F> {
    pub out: String,
    pub refused: Vec<String>,
    pub notes: Vec<String>,
    format: PhantomData<F>,
}

impl<F: Format> Writer<F> {
    pub fn new() -> Self {
        Writer {
            out: String::new(),
            refused: Vec::new(),
            notes: Vec::new(),
            format: PhantomData,
        }
    }

    pub fn line(&mut self, text: impl AsRef<str>) {
        self.out.push_str(text.as_ref());
        self.out.push('\n');
    }

    /// A unit vector the reader rebuilds through `reads`; a note when it cannot to the bit.
    pub fn direction(&mut self, what: impl FnOnce() -> String, v: DVec3, reads: fn(DVec3) -> DVec3) -> String {
        let (w, exact) = exact::direction(v, reads);
        if !exact {
            self.notes
                .push(format!("{}: reads back within rounding, not to the bit", what()));
        }
        F::vec3(w)
    }

    /// The text and its notes, or every reason the format refused.
    pub fn finish(self) -> Result<Written, Refused> {
        if !self.refused.is_empty() {
            return Err(Refused {
                format: F::NAME,
                reasons: self.refused,
            });
        }
        Ok(Written {
            text: self.out,
            notes: self.notes,
        })
    }
}
