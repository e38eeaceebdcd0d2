//! The one error every bake, map view and pyramid update gives for the buffers and
//! ranges it is handed (`cone::BakeError`, `maxmip::PyramidError` and
//! `safety::SafetyError` are this type).

use core::fmt;

/// A buffer or range a bake, a map view or an update cannot use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BufferError {
    /// A slice is shorter than needed.
    TooShort {
        /// Which slice: `scratch`, `output`, `map`, `pyramid`.
        what: &'static str,
        /// Elements needed.
        needed: usize,
        /// Elements given.
        given: usize,
    },
    /// A row range leaves the map.
    BadRows,
    /// A rectangle is reversed or reaches outside the field.
    BadRect,
}

impl fmt::Display for BufferError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BufferError::TooShort {
                what,
                needed,
                given,
            } => write!(f, "{what}: {given} elements given, {needed} needed"),
            BufferError::BadRows => write!(f, "row range leaves the map"),
            BufferError::BadRect => write!(f, "rectangle reversed or outside the field"),
        }
    }
}

/// `TooShort` unless the slice `what` of `given` elements holds `needed`.
#[cfg_attr(not(any(feature = "maxmip", feature = "safety")), allow(dead_code))]
pub(crate) fn check(what: &'static str, needed: usize, given: usize) -> Result<(), BufferError> {
    if given < needed {
        Err(BufferError::TooShort {
            what,
            needed,
            given,
        })
    } else {
        Ok(())
    }
}
