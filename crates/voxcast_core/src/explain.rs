//! The method's formula for one sample of a breakdown with that sample's own numbers put in,
//! and the final pixel's — the text the sandbox's breakdown panel shows and `voxcast trace`
//! prints, so both teach the same arithmetic.
//!
//! Each equation is written `name = expression = result` with the numbers rounded by
//! [`crate::numbers::sig`], and the expression is the update of the order actually in use:
//! front to back `C_k = C_(k−1) + (1 − O_(k−1))·α_k·c_k`, back to front (Levoy 1988)
//! `C_k = C_(k−1)·(1 − α_k) + α_k·c_k`. A test evaluates every printed expression from its
//! printed numbers and checks it reaches the printed result.

mod shading;

pub use shading::shading;

use crate::breakdown::RayTrace;
use crate::composite::{Method, Order};
use crate::numbers::{sig, sig3, sig64};

/// The explanation of sample `k` (the last sample when `None`): the method's rule in symbols,
/// then its equations with numbers, one a line.
pub fn formula(t: &RayTrace, k: Option<usize>) -> String {
    let k = k.or(t.samples.len().checked_sub(1));
    let Some((k, s)) = k.and_then(|k| t.samples.get(k).map(|s| (k, s))) else {
        return format!(
            "No samples: the pixel shows the background.\n{}",
            pixel_equation(t)
        );
    };
    let body = match t.method {
        Method::Accumulate => {
            let prev = k
                .checked_sub(1)
                .and_then(|j| t.samples.get(j))
                .map_or([0.0; 4], |p| p.composite_after);
            let (c_prev, o_prev) = ([prev[0], prev[1], prev[2]], prev[3]);
            let a = s.alpha_corrected;
            let after = s.composite_after;
            let c_after = [after[0], after[1], after[2]];
            match t.order {
                Order::FrontToBack => format!(
                    "Accumulate, front to back, sample {}:\n\
                     C_k = C_(k−1) + (1 − O_(k−1))·α_k·c_k,  O_k = O_(k−1) + (1 − O_(k−1))·α_k\n\
                     C = {} + (1 − {})·{}·{} = {}\n\
                     O = {} + (1 − {})·{} = {}",
                    s.index,
                    sig3(c_prev),
                    sig(o_prev),
                    sig(a),
                    sig3(s.color),
                    sig3(c_after),
                    sig(o_prev),
                    sig(o_prev),
                    sig(a),
                    sig(after[3]),
                ),
                Order::BackToFront => format!(
                    "Accumulate, back to front (Levoy), sample {} (visited from the far end):\n\
                     C_k = C_(k−1)·(1 − α_k) + α_k·c_k,  O_k = O_(k−1)·(1 − α_k) + α_k\n\
                     C = {}·(1 − {}) + {}·{} = {}\n\
                     O = {}·(1 − {}) + {} = {}",
                    s.index,
                    sig3(c_prev),
                    sig(a),
                    sig(a),
                    sig3(s.color),
                    sig3(c_after),
                    sig(o_prev),
                    sig(a),
                    sig(a),
                    sig(after[3]),
                ),
            }
        }
        Method::Average | Method::Maximum | Method::Minimum => {
            let mut text = format!(
                "{}: mean = Σv / n, maximum = max(v), minimum = min(v); sample {} has v = {}",
                t.method.name(),
                s.index,
                sig(s.reconstruction.value)
            );
            if let Some(st) = s.stats_after {
                text.push_str(&format!(
                    "\nafter {} samples: maximum {}, minimum {}\nmean = {} / {} = {}",
                    st.count,
                    sig(st.max),
                    sig(st.min),
                    sig64(st.sum),
                    st.count,
                    sig64(st.sum / st.count.max(1) as f64),
                ));
            }
            if let Some(v) = t.projected_value {
                text.push_str(&format!(
                    "\nthe projected value {} is coloured by the transfer function: \
                     C = colour·opacity = {}, O = {}",
                    sig(v),
                    sig3(t.color),
                    sig(t.opacity)
                ));
            }
            text
        }
        Method::Sum => {
            let mut text = format!(
                "Sum: S = Σv·Δs, Δs the length a sample stands for in voxels; sample {} has v = {}",
                s.index,
                sig(s.reconstruction.value)
            );
            if let Some(st) = s.stats_after {
                text.push_str(&format!(
                    "\nafter {} samples: Σv = {}",
                    st.count,
                    sig64(st.sum)
                ));
            }
            if let Some(d) = t.sum {
                let [a, b] = d.range;
                let [lo, hi] = d.table;
                text.push_str(&format!(
                    "\nS = {}·{} = {}\n                     where S falls in the sum range: (S − a)/(b − a) = ({} − {})/({} − {}),                      kept within 0 and 1: {}\n                     table value = lo + (hi − lo)·fraction = {} + ({} − {})·{} = {}\n                     its colour: C = colour·opacity = {}, O = {}",
                    sig64(d.values),
                    sig(d.ds_voxels),
                    sig(d.sum),
                    sig(d.sum),
                    sig(a),
                    sig(b),
                    sig(a),
                    sig(d.fraction),
                    sig(lo),
                    sig(hi),
                    sig(lo),
                    sig(d.fraction),
                    sig(d.table_value),
                    sig3(t.color),
                    sig(t.opacity)
                ));
            }
            text
        }
        Method::First => match &t.first_hit {
            Some(h) => {
                // The steps' t with the digits that tell them apart (and from the bracket).
                let ts: Vec<f32> = std::iter::once(h.bracket[0])
                    .chain(h.refinement.iter().map(|r| r.t))
                    .chain([h.bracket[1]])
                    .collect();
                let printed = crate::numbers::sig_apart(&ts);
                let steps: Vec<String> = h
                    .refinement
                    .iter()
                    .zip(&printed[1..])
                    .map(|(r, t)| format!("t = {t} (v = {})", sig(r.value)))
                    .collect();
                let found = if h.bracket[0] == h.bracket[1] {
                    format!(
                        "First: the first sample (t = {}) is already at or above the target: the \
                         ray hits where it enters the volume;\n",
                        sig(h.bracket[0])
                    )
                } else {
                    format!(
                        "First: the value rises to the target between the samples at t = {} \
                         (below it) and t = {} (at or above it);\n\
                         refinement (bisection, then linear interpolation): {}\n",
                        sig(h.bracket[0]),
                        sig(h.bracket[1]),
                        steps.join(", then ")
                    )
                };
                format!(
                    "{found}hit at t = {}, position {}, value {}, colour {} (opacity {}), shaded {}",
                    sig(h.t),
                    sig3(h.p_world),
                    sig(h.value),
                    sig3([h.tf_rgba[0], h.tf_rgba[1], h.tf_rgba[2]]),
                    sig(h.tf_rgba[3]),
                    sig3(h.color)
                )
            }
            None => format!(
                "First: no sample at or above the target up to sample {} (v = {}): the pixel \
                 shows the background",
                s.index,
                sig(s.reconstruction.value)
            ),
        },
    };
    format!("{body}\n{}", pixel_equation(t))
}

/// The pixel over the background: `pixel = C + (1 − O)·background`.
fn pixel_equation(t: &RayTrace) -> String {
    format!(
        "pixel = C + (1 − O)·background = {} + (1 − {})·{} = {}",
        sig3(t.color),
        sig(t.opacity),
        sig3(t.background),
        sig3(t.pixel)
    )
}
