//! The lanes' batch of eight: positions located, queued in order, and evaluated together —
//! records gathered, value and gradient blended, the table looked up, the colour shaded — with
//! the scalar march's operations in its order (see `lanes.rs`).

use super::*;

/// Eight positions located: their index `k` and `t`, the cell's record index and the
/// fractions inside it.
pub(super) struct Located<S: Simd> {
    pub(super) k: S::I,
    pub(super) t: S::F,
    pub(super) base: S::I,
    pub(super) fx: S::F,
    pub(super) fy: S::F,
    pub(super) fz: S::F,
}

impl Pending {
    /// Queues the positions of `located` whose bit is set in `visible`, in order,
    /// behind those waiting; the range of `base` they took. Fewer than [`LANES`] may be
    /// waiting.
    #[inline(always)]
    pub(super) fn push<S: Simd>(
        &mut self,
        s: S,
        visible: u32,
        located: &Located<S>,
    ) -> std::ops::Range<usize> {
        let n = self.n;
        assert!(n < LANES);
        let order = s.order(visible);
        // SAFETY: n < 8, so lanes n .. n + 8 lie in the arrays of sixteen.
        unsafe {
            s.pack_i(self.k.as_mut_ptr().add(n), located.k, order);
            s.pack_i(self.base.as_mut_ptr().add(n), located.base, order);
            s.pack(self.t.as_mut_ptr().add(n), located.t, order);
            s.pack(self.fx.as_mut_ptr().add(n), located.fx, order);
            s.pack(self.fy.as_mut_ptr().add(n), located.fy, order);
            s.pack(self.fz.as_mut_ptr().add(n), located.fz, order);
        }
        self.n = n + visible.count_ones() as usize;
        n..self.n
    }

    /// Drops the first `W` (at least `W` are waiting): those waiting behind them move to the
    /// front.
    #[inline(always)]
    pub(super) fn shift<const W: usize>(&mut self) {
        self.k.copy_within(W.., 0);
        self.base.copy_within(W.., 0);
        self.t.copy_within(W.., 0);
        self.fx.copy_within(W.., 0);
        self.fy.copy_within(W.., 0);
        self.fz.copy_within(W.., 0);
        self.n -= W;
    }
}

impl Lanes<'_> {
    /// Locates positions `k .. k + 8`: how many of them lie before `end`, and as bits which of
    /// those lie in a visible cell.
    #[inline(always)]
    pub(super) fn locate<S: Simd>(
        &self,
        s: S,
        plan: &StepPlan,
        k: u32,
        end: u32,
        (o_v, d_v): (Vec3, Vec3),
    ) -> (u32, u32, Located<S>) {
        let c = super::super::positions::cells(s, plan, k, (o_v, d_v), (self.last, self.max_lo));
        let taken = (end - k).min(LANES as u32);
        let [ix, iy, iz] = c.i;
        // VisibleCells::lookup: the brick's word, the cell's bit in it (read as 32-bit halves).
        let word = s.add_i(
            s.shr_i::<2>(ix),
            s.add_i(
                s.mul_i(s.shr_i::<2>(iy), s.splat_i(self.bricks_x)),
                s.mul_i(s.shr_i::<2>(iz), s.splat_i(self.bricks_xy)),
            ),
        );
        let three = s.splat_i(3);
        let bit = s.or_i(
            s.and_i(ix, three),
            s.or_i(
                s.shl_i::<2>(s.and_i(iy, three)),
                s.shl_i::<4>(s.and_i(iz, three)),
            ),
        );
        let half = s.add_i(s.shl_i::<1>(word), s.shr_i::<5>(bit));
        // SAFETY: every lane's cell is in the lattice (clamped), so its word exists.
        let set = unsafe { s.bit_set(self.words.as_ptr() as *const i32, half, bit) };
        let visible = set & ((1u32 << taken) - 1);
        let [fx, fy, fz] = c.f;
        let out = Located {
            k: c.k,
            t: c.t,
            base: c.corner(s, self.nx, self.nxy),
            fx,
            fy,
            fz,
        };
        (taken, visible, out)
    }

    /// Evaluates the pending samples: `value_and_gradient_in_cell`, `Grid::to_data`,
    /// `Lut::lookup_if_visible` and `shade` for eight lanes, operation for operation; for a
    /// full batch (`plan` given) also the opacity correction where [`Lanes::correct_batch`]
    /// can.
    ///
    /// # Safety
    /// Every pending base of the first eight is the lower corner of a cell of the lattice.
    #[inline(always)]
    pub(super) unsafe fn evaluate<S: Simd, const W: usize>(
        &self,
        s: S,
        p: &Pending,
        rl: &RayLights,
        plan: Option<&StepPlan>,
    ) -> Evaluated {
        // SAFETY: the caller's.
        let b = unsafe { self.blend_records::<S, W>(s, p) };
        let half = s.splat(0.5);
        let gs = self.gradient_scale;
        let grad = [
            s.mul(s.mul(b[0], half), s.splat(gs.x)),
            s.mul(s.mul(b[1], half), s.splat(gs.y)),
            s.mul(s.mul(b[2], half), s.splat(gs.z)),
        ];
        let v = s.add(s.mul(b[3], s.splat(self.slope)), s.splat(self.intercept));
        // The table: position, the two entries, opaque where either has opacity.
        let zero = s.splat(0.0);
        let x = s.min(
            s.max(
                s.mul(s.sub(v, s.splat(self.lut_lo)), s.splat(self.lut_scale)),
                zero,
            ),
            s.splat(self.lut_last),
        );
        let i = s.min_i(s.trunc(x), s.splat_i(self.lut_max_index));
        let f = s.sub(x, s.to_f(i));
        // SAFETY: i ≤ len − 2, so entries i and i + 1 exist.
        let (a, bb) = unsafe { self.entry_pairs::<S, W>(s, i) };
        let opaque = s.or(s.gt(a[3], zero), s.gt(bb[3], zero));
        let rgba = [
            lerp(s, a[0], bb[0], f),
            lerp(s, a[1], bb[1], f),
            lerp(s, a[2], bb[2], f),
            lerp(s, a[3], bb[3], f),
        ];
        if s.bits(opaque) == 0 {
            // No lane has opacity (neither entry has any): the composite passes over every
            // lane, so there is nothing to shade or correct.
            return Evaluated {
                alpha: [0.0; LANES],
                opaque: 0,
                rgb: [[0.0; LANES]; 3],
                corrected: false,
            };
        }
        let alpha = s.and(opaque, rgba[3]);
        let color = [rgba[0], rgba[1], rgba[2]];
        let shaded = self.shade(s, color, grad, rl);
        let corrected = match plan {
            Some(plan) => self.correct_batch::<S, W>(s, plan, p, alpha),
            None => None,
        };
        let alpha = corrected.unwrap_or(alpha);
        let mut out = Evaluated {
            alpha: [0.0; LANES],
            // Not `≤ 0`, as the scalar composite asks (unordered: a NaN is blended there too).
            opaque: s.bits(s.not_le(alpha, zero)),
            rgb: [[0.0; LANES]; 3],
            corrected: corrected.is_some(),
        };
        // SAFETY: eight lanes each.
        unsafe {
            s.store(out.alpha.as_mut_ptr(), alpha);
            for (ch, c) in shaded.iter().enumerate() {
                s.store(out.rgb[ch].as_mut_ptr(), *c);
            }
        }
        out
    }

    /// `correct_opacity` for a full batch at once, where it is the same for every lane: each
    /// sample stands for exactly one step (`segment_length`'s interior case) and the step's
    /// power is one the scalar code takes without `powf` ([`Lanes::batch_power`]): ½ is a
    /// square root and 2 a square, correctly rounded in lanes as alone. `None` otherwise (the
    /// composite then corrects sample by sample).
    #[inline(always)]
    pub(super) fn correct_batch<S: Simd, const W: usize>(
        &self,
        s: S,
        plan: &StepPlan,
        p: &Pending,
        alpha: S::F,
    ) -> Option<S::F> {
        let e = self.batch_power.filter(|_| self.correction)?;
        // SAFETY: the arrays hold sixteen lanes; the batch is the first eight.
        let (k, t) = unsafe { (s.load_i(p.k.as_ptr()), s.load(p.t.as_ptr())) };
        // segment_length's interior: k > 0, not the last sample, t + dt/2 ≤ t_exit.
        let first = s.eq_i(k, s.splat_i(0));
        let last = if plan.capped {
            s.splat(0.0)
        } else {
            s.eq_i(k, s.splat_i(plan.count as i32 - 1))
        };
        let inside = s.le(s.add(t, s.splat(0.5 * plan.dt)), s.splat(plan.t_exit));
        let edge = s.or(first, last);
        let batch = (1u32 << W) - 1;
        if s.bits(s.and_not(edge, inside)) & batch != batch {
            return None;
        }
        let one = s.splat(1.0);
        let keep = s.sub(one, alpha);
        let raised = if e == 1.0 {
            alpha
        } else if e == 0.5 {
            s.sub(one, s.sqrt(keep))
        } else {
            s.sub(one, s.mul(keep, keep))
        };
        // α ≤ 0 stays (the composite passes over it); α ≥ 1 is 1 (the step is positive).
        let opaque = s.ge(alpha, one);
        let clear = s.le(alpha, s.splat(0.0));
        Some(s.select(s.select(raised, one, opaque), alpha, clear))
    }

    /// `value_and_gradient_in_cell` for the pending lanes: each lane's cell read as four pairs
    /// of records side by side along x (16 bytes each), blended x, y, z in its own lanes, then
    /// the eight results turned into one vector per channel (differences x, y, z, raw value).
    /// The pairs are regrouped as 64-bit integers before widening — `[c000 | c001]` against
    /// `[c100 | c101]`, `[c010 | c011]` against `[c110 | c111]` — so that the x blend gives
    /// `[x00 | x01]` and `[x10 | x11]` and the y blend `[y0 | y1]` with no move across AVX2's
    /// halves (`vperm2f128`: one micro-operation on Zen 4, eight on Zen 1).
    ///
    /// # Safety
    /// Every pending base of the first eight is the lower corner of a cell whose upper x
    /// corner is the next record (`Lanes::new` takes volumes with more than one point along x
    /// only).
    #[inline(always)]
    pub(super) unsafe fn blend_records<S: Simd, const W: usize>(
        &self,
        s: S,
        p: &Pending,
    ) -> [S::F; 4] {
        let [_, _, dy, _, dz, _, dzy, _] = self.corners;
        let records = self.records.as_ptr();
        let mut rows = [s.zero_h(); LANES];
        for (lane, row) in rows.iter_mut().enumerate().take(W) {
            let at = records.wrapping_add(p.base[lane] as usize);
            // SAFETY: the cell's corners (so both records of each pair) are in the lattice.
            let (p00, p10, p01, p11) = unsafe {
                (
                    pair_at(s, at, 0),
                    pair_at(s, at, dy),
                    pair_at(s, at, dz),
                    pair_at(s, at, dzy),
                )
            };
            let (tx, ty) = (s.splat(p.fx[lane]), s.splat(p.fy[lane]));
            // [x00 | x01] and [x10 | x11]: each low corner against its high one along x.
            // SAFETY: the pairs were just taken, of records nothing writes.
            let (lo, hi) = unsafe { s.widen_pairs(p00, p01) };
            let x0 = lerp(s, lo, hi, tx);
            // SAFETY: as above.
            let (lo, hi) = unsafe { s.widen_pairs(p10, p11) };
            let x1 = lerp(s, lo, hi, tx);
            // [y0 | y1] = [x00 | x01] against [x10 | x11].
            let (y0, y1) = s.halves(lerp(s, x0, x1, ty));
            *row = s.lerp_h(y0, y1, p.fz[lane]);
        }
        s.columns(rows)
    }

    /// Table entries `i` and `i + 1` of each lane as columns (red, green, blue, opacity):
    /// each lane's two entries read as rows of four and turned around, which costs less than
    /// eight gathers (on Zen 1 a gather of eight is some twenty micro-operations).
    ///
    /// # Safety
    /// Every lane's `i` is at most the table's length − 2.
    #[inline(always)]
    pub(super) unsafe fn entry_pairs<S: Simd, const W: usize>(
        &self,
        s: S,
        i: S::I,
    ) -> ([S::F; 4], [S::F; 4]) {
        let mut at = [0i32; LANES];
        // SAFETY: eight lanes into eight slots.
        unsafe { s.store_i(at.as_mut_ptr(), i) };
        let entries = self.entries.as_ptr() as *const f32;
        let (mut lo, mut hi) = ([s.zero_h(); LANES], [s.zero_h(); LANES]);
        for lane in 0..W {
            // SAFETY: the caller's bound; an entry is four floats.
            unsafe {
                let row = entries.add(4 * at[lane] as usize);
                lo[lane] = s.load_h(row);
                hi[lane] = s.load_h(row.add(4));
            }
        }
        (s.columns(lo), s.columns(hi))
    }

    /// `crate::shade::shade` for eight lanes with directional lights, operation for operation.
    #[inline(always)]
    pub(super) fn shade<S: Simd>(
        &self,
        s: S,
        c: [S::F; 3],
        grad: [S::F; 3],
        rl: &RayLights,
    ) -> [S::F; 3] {
        let len = s.sqrt(s.add(
            s.add(s.mul(grad[0], grad[0]), s.mul(grad[1], grad[1])),
            s.mul(grad[2], grad[2]),
        ));
        // lit: len > threshold and finite (ordered comparisons: NaN is neither).
        let lit = s.and(
            s.gt(len, s.splat(self.threshold)),
            s.lt(len, s.splat(f32::INFINITY)),
        );
        let inv = s.div(s.splat(-1.0), len);
        let mut n = [
            s.mul(grad[0], inv),
            s.mul(grad[1], inv),
            s.mul(grad[2], inv),
        ];
        let zero = s.splat(0.0);
        if self.two_sided {
            let back = s.lt(dot(s, &n, rl.view), zero);
            let sign = s.and(back, s.splat(-0.0));
            n = [s.xor(n[0], sign), s.xor(n[1], sign), s.xor(n[2], sign)];
        }
        let tint = if self.levoy { c } else { [s.splat(1.0); 3] };
        let (mut diffuse, mut specular) = ([zero; 3], [zero; 3]);
        for &(l, color, half) in &rl.lights[..self.light_count] {
            let n_dot_l = dot(s, &n, l);
            let lambert = s.max(n_dot_l, zero);
            let base = if self.blinn {
                dot(s, &n, half)
            } else {
                // (n·(2·n_dot_l) − l)·view
                let two = s.mul(s.splat(2.0), n_dot_l);
                let r = [
                    s.sub(s.mul(n[0], two), s.splat(l.x)),
                    s.sub(s.mul(n[1], two), s.splat(l.y)),
                    s.sub(s.mul(n[2], two), s.splat(l.z)),
                ];
                dot(s, &r, rl.view)
            };
            let spec = s.and(
                s.gt(n_dot_l, zero),
                power(s, s.max(base, zero), self.exponent),
            );
            let kd_lambert = s.mul(s.splat(self.kd), lambert);
            let ks_spec = s.mul(s.splat(self.ks), spec);
            let light = color.to_array();
            for ch in 0..3 {
                let d = s.mul(c[ch], s.mul(s.splat(light[ch]), kd_lambert));
                let sp = s.mul(s.mul(tint[ch], s.splat(light[ch])), ks_spec);
                diffuse[ch] = s.add(diffuse[ch], d);
                specular[ch] = s.add(specular[ch], sp);
            }
        }
        // A loop, not `map` with a closure: the closure was left out of line (a call per
        // channel, its vectors through memory).
        let mut shaded = [zero; 3];
        for (ch, out) in shaded.iter_mut().enumerate() {
            let ambient = s.mul(c[ch], s.splat(self.ka));
            let sum = s.add(s.add(ambient, diffuse[ch]), specular[ch]);
            let clamped = s.min(s.max(sum, zero), s.splat(1.0));
            *out = s.select(c[ch], clamped, lit);
        }
        shaded
    }
}

// The helpers below are functions, not closures: a closure in these generic functions is
// compiled without the backend's instructions and may be left out of line, with every
// intrinsic in it a call.

/// `a · b` for eight vectors `a` and one `b`, summed x, y, z in that order.
#[inline(always)]
pub(super) fn dot<S: Simd>(s: S, a: &[S::F; 3], b: Vec3) -> S::F {
    s.add(
        s.add(s.mul(a[0], s.splat(b.x)), s.mul(a[1], s.splat(b.y))),
        s.mul(a[2], s.splat(b.z)),
    )
}

/// Two records side by side (16 bytes) at record `at + o`.
///
/// # Safety
/// Records `at + o` and `at + o + 1` exist.
#[inline(always)]
pub(super) unsafe fn pair_at<S: Simd>(s: S, at: *const crate::sample::Differences, o: i32) -> S::R {
    // SAFETY: the caller's.
    unsafe { s.load_pair(at.add(o as usize) as *const u8) }
}

/// `crate::shade::power` for a whole exponent, lane by lane: the same squarings and products.
#[inline(always)]
pub(super) fn power<S: Simd>(s: S, x: S::F, n: u32) -> S::F {
    let (mut base, mut e, mut acc) = (x, n, s.splat(1.0));
    while e > 0 {
        if e & 1 == 1 {
            acc = s.mul(acc, base);
        }
        base = s.mul(base, base);
        e >>= 1;
    }
    acc
}
