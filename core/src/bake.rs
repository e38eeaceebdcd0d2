//! One bake interface for every baked map: its size, its scratch, the bake of a row
//! range and the whole bake, chosen by the map's description ([`crate::ktx2::Desc`]).
//! The C API's `hf_bake*` functions and the tools bake through it; the per-method
//! modules keep their own typed functions, which this calls.
//!
//! A bake runs in three steps, as meshoptimizer's do: ask the sizes ([`Spec::map_len`],
//! [`Spec::scratch_len`]), fill the scratch once ([`Spec::prepare`]), then bake row
//! ranges ([`Spec::bake_rows`], any order, on any threads, sharing the scratch). The
//! maximum-mipmap pyramid has no scratch and bakes as one row here (its levels depend on
//! each other; `maxmip::bake_rows` splits it by level).

use crate::buffer::BufferError;
#[cfg(feature = "cone")]
use crate::cone::{self, Cone};
use crate::field::HeightField;
use crate::ktx2::{self, DataMut, Desc, MapKind};
#[cfg(feature = "qdm")]
use crate::qdm::Qdm;
#[cfg(feature = "relaxed")]
use crate::relaxed::Relaxed;
use core::fmt;
use core::ops::Range;

/// A map to bake: its description (map, field size, cap, ray classes, tolerance) and
/// the bake choices a description does not record.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spec {
    /// Which map, of which size, baked for which cap, classes and tolerance.
    pub desc: Desc,
    /// Safety distances: every distance at least 1 (the paper's "strictly positive"
    /// variant; **not exact**). Other maps ignore it.
    pub positive: bool,
    /// Cylinder–cone shapes: the cone slope from the N-buffers (every triangle limiting;
    /// conservative, faster to bake) instead of the exact one over the limiting
    /// triangles. Other maps ignore it.
    pub nbuffer_slope: bool,
}

/// Why a bake could not run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Error {
    /// A buffer too short or a row range outside the map.
    Buffer(BufferError),
    /// The description is invalid ([`ktx2::Ktx2Error::BadDesc`]'s cases).
    BadDesc,
    /// The field is not of the description's size.
    WrongField,
    /// The output's element type is not the map's (`f32` for an 8-bit map or back).
    WrongType,
    /// The map's method is not in this build (its Cargo feature is off).
    NotBuilt(MapKind),
    /// The occluders are not the ray set's ([`crate::rayset::Rays::check_occluders`]).
    Occluders(crate::rayset::RaysError),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Buffer(e) => e.fmt(f),
            Error::BadDesc => write!(f, "invalid map description"),
            Error::WrongField => write!(f, "the field is not of the map's size"),
            Error::WrongType => write!(f, "the output's element type is not the map's"),
            Error::NotBuilt(m) => write!(f, "{} maps are not in this build", m.method()),
            Error::Occluders(e) => e.fmt(f),
        }
    }
}

impl From<BufferError> for Error {
    fn from(e: BufferError) -> Error {
        Error::Buffer(e)
    }
}

impl Spec {
    /// The map of `desc` with the default choices (exact: neither `positive` nor the
    /// N-buffer slope).
    pub fn new(desc: Desc) -> Spec {
        Spec {
            desc,
            positive: false,
            nbuffer_slope: false,
        }
    }

    /// Elements (`f32`s or bytes, as [`Spec::is_float`]) of the map's texels.
    pub fn map_len(&self) -> Result<usize, Error> {
        ktx2::map_len(&self.desc).map_err(|_| Error::BadDesc)
    }

    /// Whether the map's elements are `f32`s (else bytes).
    pub fn is_float(&self) -> bool {
        self.desc.map.format().is_float()
    }

    /// Floats of the scratch [`Spec::prepare`] fills (0 for the heights and the pyramid).
    pub fn scratch_len(&self) -> usize {
        let [w, h] = [self.desc.width, self.desc.height];
        let _ = (w, h);
        match self.desc.map {
            MapKind::Heights | MapKind::MaxMip => 0,
            #[cfg(feature = "safety")]
            MapKind::Safety | MapKind::SafetyIsotropic | MapKind::Radius => {
                crate::safety::scratch_len(w, h)
            }
            #[cfg(feature = "safety")]
            MapKind::Cc => {
                crate::safety::scratch_len(w, h)
                    + crate::safety::cc::nbuffer_len(w, h, self.desc.cap)
            }
            #[cfg(feature = "cone")]
            MapKind::Cone | MapKind::Relaxed | MapKind::Qdm => cone::scratch_len(w, h),
            #[allow(unreachable_patterns)]
            _ => 0,
        }
    }

    /// Rows of the row bake: sample rows (H) for the heights, safety, cylinder–cone,
    /// radius and relaxed maps, cell rows (H − 1) for the cone and QDM maps, one for the
    /// pyramid.
    pub fn rows(&self) -> u32 {
        match self.desc.map {
            MapKind::MaxMip => 1,
            MapKind::Cone | MapKind::Qdm => self.desc.height.saturating_sub(1),
            _ => self.desc.height,
        }
    }

    /// Elements per row of the row bake ([`Spec::map_len`] / [`Spec::rows`]).
    pub fn row_len(&self) -> Result<usize, Error> {
        Ok(self.map_len()? / self.rows().max(1) as usize)
    }

    /// Checks that `hf` is of the description's size.
    fn check_field(&self, hf: &HeightField) -> Result<(), Error> {
        self.map_len()?;
        if [hf.width(), hf.height()] != [self.desc.width, self.desc.height] {
            return Err(Error::WrongField);
        }
        Ok(())
    }

    /// Fills `scratch` (at least [`Spec::scratch_len`] floats) with what every row bake
    /// of `hf` reads. O(cells), one thread.
    pub fn prepare(&self, hf: &HeightField, scratch: &mut [f32]) -> Result<(), Error> {
        self.check_field(hf)?;
        crate::buffer::check("scratch", self.scratch_len(), scratch.len())?;
        match self.desc.map {
            MapKind::Heights | MapKind::MaxMip => {}
            #[cfg(feature = "safety")]
            MapKind::Safety | MapKind::SafetyIsotropic | MapKind::Radius => {
                crate::safety::prepare(hf, scratch)?
            }
            #[cfg(feature = "safety")]
            MapKind::Cc => {
                let (strips, nb) =
                    scratch.split_at_mut(crate::safety::scratch_len(hf.width(), hf.height()));
                crate::safety::prepare(hf, strips)?;
                crate::safety::cc::prepare_nbuffer(hf, self.desc.cap, nb)?;
            }
            #[cfg(feature = "cone")]
            MapKind::Cone | MapKind::Relaxed | MapKind::Qdm => cone::prepare(hf, scratch)?,
            #[allow(unreachable_patterns)]
            m => return Err(Error::NotBuilt(m)),
        }
        Ok(())
    }

    /// Bakes rows `rows` of `hf`'s map into `out`, which holds those rows only
    /// ([`Spec::row_len`] elements a row, from element `rows.start · row_len` of the
    /// whole map), reading the `scratch` [`Spec::prepare`] filled. Rows are independent:
    /// any job system may bake disjoint ranges at once. A ray set with occluders is
    /// baked without them (safe for it, less tight): [`Spec::bake_rows_over`] takes them.
    pub fn bake_rows(
        &self,
        hf: &HeightField,
        scratch: &[f32],
        rows: Range<u32>,
        out: DataMut,
    ) -> Result<(), Error> {
        self.bake_rows_over(hf, &[], scratch, rows, out)
    }

    /// [`Spec::bake_rows`] with the occluders of the description's ray set (refused
    /// unless they are the set's; none for a set without occluders). Maps without a
    /// ray set (all but safety distances and cylinder–cones) ignore them.
    pub fn bake_rows_over(
        &self,
        hf: &HeightField,
        occluders: &[crate::rayset::Occluder],
        scratch: &[f32],
        rows: Range<u32>,
        out: DataMut,
    ) -> Result<(), Error> {
        self.check_field(hf)?;
        // Only the safety-shape maps have a ray set; the others ignore occluders.
        let has_set = matches!(
            self.desc.map,
            MapKind::Safety | MapKind::SafetyIsotropic | MapKind::Cc
        );
        if has_set && !occluders.is_empty() {
            let rays = self.desc.rays;
            rays.check_occluders(occluders).map_err(Error::Occluders)?;
        }
        if rows.start > rows.end || rows.end > self.rows() {
            return Err(BufferError::BadRows.into());
        }
        crate::buffer::check("scratch", self.scratch_len(), scratch.len())?;
        let needed = rows.len() * self.row_len()?;
        let given = match &out {
            DataMut::U8(o) => o.len(),
            DataMut::F32(o) => o.len(),
        };
        crate::buffer::check("output", needed, given)?;
        if rows.is_empty() {
            // Nothing to bake (the pyramid's one row would bake it whole).
            return Ok(());
        }
        if self.is_float() != matches!(out, DataMut::F32(_)) {
            return Err(Error::WrongType);
        }
        let _ = (scratch, &rows, occluders);
        match (self.desc.map, out) {
            (MapKind::Heights, DataMut::F32(out)) => {
                let w = hf.width() as usize;
                for (row, j) in out.chunks_exact_mut(w).zip(rows) {
                    let from = j as usize * hf.stride();
                    row.copy_from_slice(&hf.samples()[from..from + w]);
                }
                Ok(())
            }
            #[cfg(feature = "maxmip")]
            (MapKind::MaxMip, DataMut::F32(out)) => Ok(crate::maxmip::bake(hf, out)?),
            #[cfg(feature = "cone")]
            (MapKind::Cone, DataMut::F32(out)) => {
                Ok(cone::bake_rows::<Cone>(hf, scratch, rows, out)?)
            }
            #[cfg(feature = "relaxed")]
            (MapKind::Relaxed, DataMut::F32(out)) => {
                Ok(cone::bake_rows::<Relaxed>(hf, scratch, rows, out)?)
            }
            #[cfg(feature = "qdm")]
            (MapKind::Qdm, DataMut::F32(out)) => {
                Ok(cone::bake_rows::<Qdm>(hf, scratch, rows, out)?)
            }
            #[cfg(feature = "safety")]
            (MapKind::Safety | MapKind::SafetyIsotropic, DataMut::U8(out)) => {
                use crate::safety::{self, Options, Variant};
                let variant = match self.desc.map {
                    MapKind::Safety => Variant::Directional,
                    _ => Variant::Isotropic,
                };
                let opts = Options {
                    variant,
                    positive: self.positive,
                    cap: self.desc.cap,
                };
                let classes = self.desc.classes;
                let rays = self.rays_on(hf, occluders);
                Ok(safety::bake_rows_classes(
                    hf, scratch, &rays, classes, rows, opts, out,
                )?)
            }
            #[cfg(feature = "safety")]
            (MapKind::Cc, DataMut::U8(out)) => {
                use crate::safety::cc::{self, CcOptions, Slope};
                let (strips, nb) =
                    scratch.split_at(crate::safety::scratch_len(hf.width(), hf.height()));
                let opts = CcOptions {
                    slope: if self.nbuffer_slope {
                        Slope::NBuffer
                    } else {
                        Slope::Exact
                    },
                    cap: self.desc.cap,
                };
                Ok(cc::bake_rows_with(
                    hf,
                    strips,
                    nb,
                    &self.rays_on(hf, occluders),
                    self.desc.classes,
                    rows,
                    opts,
                    out,
                )?)
            }
            #[cfg(feature = "safety")]
            (MapKind::Radius, DataMut::U8(out)) => {
                let opts = crate::radius::BakeOptions {
                    tolerance: self.desc.tolerance,
                    cap: self.desc.cap,
                };
                Ok(crate::radius::bake_rows(hf, scratch, rows, opts, out)?)
            }
            (m, _) => Err(Error::NotBuilt(m)),
        }
    }

    /// The description's ray set as the bake tests it, with `occluders` (checked by
    /// [`Spec::bake_rows_over`]) where given.
    #[cfg(feature = "safety")]
    fn rays_on<'a>(
        &self,
        hf: &'a HeightField<'a>,
        occluders: &'a [crate::rayset::Occluder],
    ) -> crate::safety::RaysOn<'a> {
        let rays = self.desc.rays;
        rays.on_over(hf, occluders).unwrap_or_else(|_| rays.on(hf))
    }

    /// Prepares `scratch` and bakes every row of `hf`'s map into `out` (at least
    /// [`Spec::map_len`] elements), one thread.
    pub fn bake(&self, hf: &HeightField, scratch: &mut [f32], out: DataMut) -> Result<(), Error> {
        self.prepare(hf, scratch)?;
        self.bake_rows(hf, scratch, 0..self.rows(), out)
    }
}

/// A map's texels in a buffer of their own (`alloc`): what [`Spec::bake_owned`] bakes.
#[cfg(feature = "alloc")]
#[derive(Clone, Debug, PartialEq)]
pub enum Texels {
    /// A float map.
    F32(alloc::vec::Vec<f32>),
    /// An 8-bit map.
    U8(alloc::vec::Vec<u8>),
}

#[cfg(feature = "alloc")]
impl Texels {
    /// The texels as a slice of their type.
    pub fn data(&self) -> ktx2::Data<'_> {
        match self {
            Texels::F32(v) => ktx2::Data::F32(v),
            Texels::U8(v) => ktx2::Data::U8(v),
        }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        match self {
            Texels::F32(v) => v.len() * 4,
            Texels::U8(v) => v.len(),
        }
    }
}

#[cfg(feature = "alloc")]
impl Spec {
    /// Bakes `hf`'s whole map into buffers of its own, one thread.
    pub fn bake_owned(&self, hf: &HeightField) -> Result<Texels, Error> {
        self.bake_owned_over(hf, &[])
    }

    /// [`Spec::bake_owned`] with the occluders of the description's ray set
    /// ([`Spec::bake_rows_over`]).
    pub fn bake_owned_over(
        &self,
        hf: &HeightField,
        occluders: &[crate::rayset::Occluder],
    ) -> Result<Texels, Error> {
        let n = self.map_len()?;
        let mut scratch = alloc::vec![0.0; self.scratch_len()];
        let mut out = match self.is_float() {
            true => Texels::F32(alloc::vec![0.0; n]),
            false => Texels::U8(alloc::vec![0; n]),
        };
        let data = match &mut out {
            Texels::F32(v) => DataMut::F32(v),
            Texels::U8(v) => DataMut::U8(v),
        };
        self.prepare(hf, &mut scratch)?;
        self.bake_rows_over(hf, occluders, &scratch, 0..self.rows(), data)?;
        Ok(out)
    }
}
