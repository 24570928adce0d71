//! Closed-form, piecewise-smooth time profiles of one kinematic channel
//! (speed, track, path angle, side-slip).
//!
//! Every piece has the rate
//! `x'(τ) = c0 + c1 cos(wτ) + c2 sin(wτ)`, `τ = t − t0`, so the value, rate
//! and rate of change are exact closed forms: a constant, a linear ramp, the
//! raised-cosine edges of a rate trapezoid and a Hann pulse are all special
//! cases. Exact derivatives are what let the simulator compute the IMU
//! increments by quadrature instead of by finite differences.

/// One piece of a channel on `[t0, t1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Piece {
    pub t0: f64,
    pub t1: f64,
    x0: f64,
    c0: f64,
    c1: f64,
    c2: f64,
    w: f64,
}

/// Value, first and second time derivative of a channel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Sample {
    pub x: f64,
    pub dx: f64,
    pub ddx: f64,
}

impl Piece {
    /// A constant value.
    pub fn hold(t0: f64, t1: f64, x0: f64) -> Self {
        Self::linear(t0, t1, x0, 0.0)
    }

    /// A constant rate `r`.
    pub fn linear(t0: f64, t1: f64, x0: f64, r: f64) -> Self {
        Self {
            t0,
            t1,
            x0,
            c0: r,
            c1: 0.0,
            c2: 0.0,
            w: 0.0,
        }
    }

    /// The rate rises from 0 to `r` as a raised cosine over the piece.
    pub fn rise(t0: f64, t1: f64, x0: f64, r: f64) -> Self {
        let w = std::f64::consts::PI / (t1 - t0);
        Self {
            t0,
            t1,
            x0,
            c0: 0.5 * r,
            c1: -0.5 * r,
            c2: 0.0,
            w,
        }
    }

    /// The rate falls from `r` to 0 as a raised cosine over the piece.
    pub fn fall(t0: f64, t1: f64, x0: f64, r: f64) -> Self {
        let w = std::f64::consts::PI / (t1 - t0);
        Self {
            t0,
            t1,
            x0,
            c0: 0.5 * r,
            c1: 0.5 * r,
            c2: 0.0,
            w,
        }
    }

    /// The value moves by `delta` with a Hann-shaped rate
    /// `(Δ/T)(1 − cos 2πτ/T)`: rate and its derivative vanish at both ends.
    pub fn hann_step(t0: f64, t1: f64, x0: f64, delta: f64) -> Self {
        let span = t1 - t0;
        Self {
            t0,
            t1,
            x0,
            c0: delta / span,
            c1: -delta / span,
            c2: 0.0,
            w: 2.0 * std::f64::consts::PI / span,
        }
    }

    /// The value leaves `x0` and returns to it, peaking at `x0 + peak`
    /// mid-way: `x = x0 + (peak/2)(1 − cos 2πτ/T)`.
    pub fn hann_pulse(t0: f64, t1: f64, x0: f64, peak: f64) -> Self {
        let w = 2.0 * std::f64::consts::PI / (t1 - t0);
        Self {
            t0,
            t1,
            x0,
            c0: 0.0,
            c1: 0.0,
            c2: 0.5 * peak * w,
            w,
        }
    }

    /// Value, rate and rate of change at `t` (clamped to the piece).
    #[inline]
    pub fn eval(&self, t: f64) -> Sample {
        let tau = (t.min(self.t1) - self.t0).max(0.0);
        if self.w == 0.0 {
            return Sample {
                x: self.x0 + self.c0 * tau,
                dx: self.c0,
                ddx: 0.0,
            };
        }
        let (s, c) = (self.w * tau).sin_cos();
        let iw = 1.0 / self.w;
        Sample {
            x: self.x0 + self.c0 * tau + self.c1 * iw * s + self.c2 * iw * (1.0 - c),
            dx: self.c0 + self.c1 * c + self.c2 * s,
            ddx: self.w * (self.c2 * c - self.c1 * s),
        }
    }

    /// The value at the end of the piece.
    pub fn end_value(&self) -> f64 {
        self.eval(self.t1).x
    }
}

/// A channel: contiguous pieces from time 0, holding its last value after
/// the end.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Channel {
    pieces: Vec<Piece>,
}

impl Channel {
    /// An empty channel starting at time `t0` with value `x0`.
    pub fn new(t0: f64, x0: f64) -> Self {
        Self {
            pieces: vec![Piece::hold(t0, t0, x0)],
        }
    }

    /// End time of the last piece.
    pub fn end_time(&self) -> f64 {
        self.pieces.last().map_or(0.0, |p| p.t1)
    }

    /// Value at the end of the last piece.
    pub fn end_value(&self) -> f64 {
        self.pieces.last().map_or(0.0, Piece::end_value)
    }

    /// Appends a piece; a gap before it is filled by holding the value.
    pub fn push(&mut self, piece: Piece) {
        self.hold_until(piece.t0);
        if piece.t1 > piece.t0 {
            self.pieces.push(piece);
        }
    }

    /// Holds the current value until `t`.
    pub fn hold_until(&mut self, t: f64) {
        let (end, x) = (self.end_time(), self.end_value());
        if t > end {
            self.pieces.push(Piece::hold(end, t, x));
        }
    }

    /// The boundaries of every piece.
    pub fn breakpoints(&self) -> impl Iterator<Item = f64> + '_ {
        self.pieces.iter().map(|p| p.t0)
    }

    /// Value and derivatives at `t`. `cursor` is the index of the piece
    /// used last: evaluation times almost always move forward, so the
    /// search is O(1) amortised (any start value is correct).
    #[inline]
    pub fn eval(&self, t: f64, cursor: &mut usize) -> Sample {
        let n = self.pieces.len();
        let mut i = (*cursor).min(n - 1);
        while i + 1 < n && t >= self.pieces[i].t1 {
            i += 1;
        }
        while i > 0 && t < self.pieces[i].t0 {
            i -= 1;
        }
        *cursor = i;
        let p = &self.pieces[i];
        let mut s = p.eval(t);
        if t > p.t1 {
            // After the end the value holds.
            s.dx = 0.0;
            s.ddx = 0.0;
        }
        s
    }
}
