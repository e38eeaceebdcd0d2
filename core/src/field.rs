//! The height field: a validated view over caller-owned samples.

use crate::world::WorldTransform;
use core::fmt;

/// Largest width or height accepted: grid coordinates stay exact in `f32` (2²⁴).
pub const MAX_SIDE: u32 = 1 << 24;

/// Why a height field was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldError {
    /// Width or height below 2 (a surface needs at least one cell).
    TooSmall,
    /// Width or height above [`MAX_SIDE`].
    TooLarge,
    /// The row stride is smaller than the width.
    StrideTooSmall,
    /// `stride × (H − 1) + W` does not fit in `usize`.
    SizeOverflow,
    /// The slice holds fewer samples than `stride × (H − 1) + W`.
    SliceTooShort {
        /// Samples needed.
        needed: usize,
        /// Samples given.
        given: usize,
    },
    /// A height (or the depth scale of an integer map) is NaN or infinite.
    NotFinite {
        /// Index of the first bad value in the slice (0 for the depth scale).
        index: usize,
    },
    /// A rectangle given to [`HeightField::revalidate_rect`] is empty or leaves the field.
    BadRect,
    /// The output buffer of an integer-map conversion is too small.
    OutputTooShort {
        /// Samples needed (W × H).
        needed: usize,
    },
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FieldError::TooSmall => write!(f, "a height field needs at least 2 x 2 samples"),
            FieldError::TooLarge => write!(f, "width and height must be at most {MAX_SIDE}"),
            FieldError::StrideTooSmall => write!(f, "row stride is smaller than the width"),
            FieldError::SizeOverflow => write!(f, "height field size overflows usize"),
            FieldError::SliceTooShort { needed, given } => {
                write!(f, "sample slice too short: {given} given, {needed} needed")
            }
            FieldError::NotFinite { index } => write!(f, "height {index} is NaN or infinite"),
            FieldError::BadRect => write!(f, "rectangle is empty or outside the field"),
            FieldError::OutputTooShort { needed } => {
                write!(f, "output buffer too short: {needed} samples needed")
            }
        }
    }
}

/// W × H heights, row-major with a row stride: sample (i, j) is `h[j * stride + i]` and
/// sits at the grid point (x = i, y = j). Validated once at construction; every march
/// may then index it without checks failing. It carries the [`WorldTransform`] that
/// places its grid in world units (the identity unless [`HeightField::with_transform`]
/// sets one).
#[derive(Clone, Copy, Debug)]
pub struct HeightField<'a> {
    samples: &'a [f32],
    width: u32,
    height: u32,
    stride: usize,
    min: f32,
    max: f32,
    transform: WorldTransform,
}

/// Number of slice elements a `width × height` map with `stride` needs, with overflow checks.
fn needed_len(width: u32, height: u32, stride: usize) -> Result<usize, FieldError> {
    if width < 2 || height < 2 {
        return Err(FieldError::TooSmall);
    }
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(FieldError::TooLarge);
    }
    if stride < width as usize {
        return Err(FieldError::StrideTooSmall);
    }
    stride
        .checked_mul(height as usize - 1)
        .and_then(|n| n.checked_add(width as usize))
        .ok_or(FieldError::SizeOverflow)
}

/// Defines the constructor `$name` from unsigned integer samples of type `$t` (the
/// integer-map constructors differ only in it and its full scale `$full`: [`convert`]).
macro_rules! from_unorm {
    ($(#[$doc:meta])* $name:ident($t:ty, $full:expr)) => {
        $(#[$doc])*
        pub fn $name(
            samples: &[$t],
            width: u32,
            height: u32,
            stride: usize,
            depth: f32,
            out: &'a mut [f32],
        ) -> Result<Self, FieldError> {
            convert(samples, width, height, stride, $full, depth, out)
        }
    };
}

impl<'a> HeightField<'a> {
    /// Validates `samples` as a `width × height` map whose rows start `stride` apart.
    pub fn new(
        samples: &'a [f32],
        width: u32,
        height: u32,
        stride: usize,
    ) -> Result<Self, FieldError> {
        let needed = needed_len(width, height, stride)?;
        if samples.len() < needed {
            return Err(FieldError::SliceTooShort {
                needed,
                given: samples.len(),
            });
        }
        let (min, max) = scan(samples, stride, 0..width as usize, 0..height as usize)?;
        Ok(HeightField {
            samples,
            width,
            height,
            stride,
            min,
            max,
            transform: WorldTransform::IDENTITY,
        })
    }

    from_unorm!(
        /// Converts 8-bit samples to heights `s / 255 × depth` into `out` (stride = width)
        /// and returns the field over `out`.
        from_u8(u8, 255.0)
    );

    from_unorm!(
        /// Converts 16-bit samples to heights `s / 65535 × depth` into `out` (stride =
        /// width) and returns the field over `out`.
        from_u16(u16, 65535.0)
    );

    /// The field after the caller changed only the samples in `[x0, x1) × [y0, y1)` of
    /// `samples` (same width, height and stride as `self`): checks just those samples
    /// and widens the height bounds to cover them, instead of reading every sample again
    /// (a 64 × 64 change in a 4096² map). The caller promises every other sample is as
    /// `self` validated it. The bounds never shrink, so they stay conservative.
    pub fn revalidate_rect<'b>(
        &self,
        samples: &'b [f32],
        x0: u32,
        y0: u32,
        x1: u32,
        y1: u32,
    ) -> Result<HeightField<'b>, FieldError> {
        if x0 >= x1 || y0 >= y1 || x1 > self.width || y1 > self.height {
            return Err(FieldError::BadRect);
        }
        let needed = needed_len(self.width, self.height, self.stride)?;
        if samples.len() < needed {
            return Err(FieldError::SliceTooShort {
                needed,
                given: samples.len(),
            });
        }
        let (min, max) = scan(
            samples,
            self.stride,
            x0 as usize..x1 as usize,
            y0 as usize..y1 as usize,
        )?;
        Ok(HeightField {
            samples,
            width: self.width,
            height: self.height,
            stride: self.stride,
            min: self.min.min(min),
            max: self.max.max(max),
            transform: self.transform,
        })
    }

    /// The same field placed in world units by `transform` (see [`crate::world`]).
    pub fn with_transform(self, transform: WorldTransform) -> Self {
        HeightField { transform, ..self }
    }
    /// The transform from grid space to world units (the identity by default).
    #[inline]
    pub fn transform(&self) -> &WorldTransform {
        &self.transform
    }
    /// Number of samples along x (W).
    #[inline]
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Number of samples along y (H).
    #[inline]
    pub fn height(&self) -> u32 {
        self.height
    }
    /// Slice elements between the starts of two rows.
    #[inline]
    pub fn stride(&self) -> usize {
        self.stride
    }
    /// Lowest height (a lower bound after [`HeightField::revalidate_rect`]).
    #[inline]
    pub fn min_height(&self) -> f32 {
        self.min
    }
    /// Highest height (an upper bound after [`HeightField::revalidate_rect`]).
    #[inline]
    pub fn max_height(&self) -> f32 {
        self.max
    }
    /// The underlying samples.
    #[inline]
    pub fn samples(&self) -> &'a [f32] {
        self.samples
    }
    /// Height of sample (i, j). Panics when out of range (a bug in the caller).
    #[inline]
    pub fn at(&self, i: u32, j: u32) -> f32 {
        debug_assert!(i < self.width && j < self.height);
        self.samples[j as usize * self.stride + i as usize]
    }
    /// The `width` samples of row `j`. Panics when out of range (a bug in the caller).
    #[inline]
    pub fn row(&self, j: u32) -> &'a [f32] {
        &self.samples[j as usize * self.stride..][..self.width as usize]
    }
    /// The four corners of cell (i, j) as `[h00, h10, h01, h11]` (h10 is at x = i + 1).
    #[inline]
    pub fn cell_corners(&self, i: u32, j: u32) -> [f32; 4] {
        // One window from the first corner to the last (one bounds check).
        let s = &self.samples[j as usize * self.stride + i as usize..][..self.stride + 2];
        [s[0], s[1], s[self.stride], s[self.stride + 1]]
    }
}

/// Lowest and highest of the samples in columns `xs` and rows `ys`, or the index of the
/// first one that is NaN or infinite.
fn scan(
    samples: &[f32],
    stride: usize,
    xs: core::ops::Range<usize>,
    ys: core::ops::Range<usize>,
) -> Result<(f32, f32), FieldError> {
    let (mut min, mut max) = (f32::INFINITY, f32::NEG_INFINITY);
    for j in ys {
        let row = &samples[j * stride + xs.start..j * stride + xs.end];
        for (i, &h) in row.iter().enumerate() {
            if !h.is_finite() {
                return Err(FieldError::NotFinite {
                    index: j * stride + xs.start + i,
                });
            }
            min = min.min(h);
            max = max.max(h);
        }
    }
    Ok((min, max))
}

/// Shared body of the integer-map constructors.
fn convert<'a, S: Copy + Into<f32>>(
    samples: &[S],
    width: u32,
    height: u32,
    stride: usize,
    full: f32,
    depth: f32,
    out: &'a mut [f32],
) -> Result<HeightField<'a>, FieldError> {
    let step = depth / full;
    if !depth.is_finite() {
        return Err(FieldError::NotFinite { index: 0 });
    }
    let needed = needed_len(width, height, stride)?;
    if samples.len() < needed {
        return Err(FieldError::SliceTooShort {
            needed,
            given: samples.len(),
        });
    }
    let w = width as usize;
    let out_len = w
        .checked_mul(height as usize)
        .ok_or(FieldError::SizeOverflow)?;
    if out.len() < out_len {
        return Err(FieldError::OutputTooShort { needed: out_len });
    }
    for j in 0..height as usize {
        let src = &samples[j * stride..j * stride + w];
        for (o, &s) in out[j * w..(j + 1) * w].iter_mut().zip(src) {
            let v = s.into() * step;
            // `sample · (depth / full)` rounds twice and may overflow for a depth near
            // `f32::MAX`; the height itself, at most `|depth|`, is then computed once
            // in f64 (finite: the issue of a finite depth reported as not finite).
            *o = if v.is_finite() {
                v
            } else {
                (f64::from(s.into()) * f64::from(depth) / f64::from(full)) as f32
            };
        }
    }
    HeightField::new(&out[..out_len], width, height, width as usize)
}
