// Twin: crates/voxcast_core/src/step.rs (`plan_steps`, `sample_t`, `first_index_from`,
// `segment_length`) and
// hash.rs (`pcg_hash`, `jitter_fraction`), computed in the same order with the same types.
#define_import_path voxcast::step

struct StepPlan {
    t_enter: f32,
    t_exit: f32,
    dt: f32,
    jitter: f32,
    count: u32,
    capped: bool,
}

/// t_k = t_enter + (j + k)·dt while t_k ≤ t_exit, at most `max_samples` of them.
fn plan_steps(t_enter: f32, t_exit: f32, dt: f32, jitter: f32, max_samples: u32) -> StepPlan {
    let span = (t_exit - t_enter) / dt - jitter;
    var wanted = 0.0;
    if span >= 0.0 {
        wanted = floor(span) + 1.0;
    }
    let capped = wanted > f32(max_samples);
    let count = select(u32(wanted), max_samples, capped);
    return StepPlan(t_enter, t_exit, dt, jitter, count, capped);
}

/// Where sample k sits: t_enter + (j + k)·dt, never past t_exit.
fn sample_t(plan: StepPlan, k: u32) -> f32 {
    return min(plan.t_enter + (plan.jitter + f32(k)) * plan.dt, plan.t_exit);
}

/// The index of the first sample at or after t, at most count: where a ray resumes after
/// skipping to t.
fn first_index_from(plan: StepPlan, t: f32) -> u32 {
    let k = ceil((t - plan.t_enter) / plan.dt - plan.jitter);
    if k <= 0.0 {
        return 0u;
    }
    if k >= f32(plan.count) {
        return plan.count;
    }
    return u32(k);
}

/// The length of ray sample k (at t_k) stands for: its cell between the midpoints to its
/// neighbours, the first starting at t_enter and the last ending at t_exit.
fn segment_length(plan: StepPlan, k: u32, t_k: f32) -> f32 {
    let half = 0.5 * plan.dt;
    let last = k + 1u == plan.count && !plan.capped;
    if k > 0u && !last && t_k + half <= plan.t_exit {
        return plan.dt; // an interior sample: dt exactly, not dt give or take t_k's rounding
    }
    var start = t_k - half;
    if k == 0u {
        start = plan.t_enter;
    }
    var end = min(t_k + half, plan.t_exit);
    if last {
        end = plan.t_exit;
    }
    return max(end - start, 0.0);
}

/// PCG-RXS-M-XS (Jarzynski & Olano 2020): wrapping u32 arithmetic, as in Rust.
fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/// A fraction in [0, 1) for pixel (x, y) and seed: the top 24 bits of the hash.
fn jitter_fraction(x: u32, y: u32, seed: u32) -> f32 {
    let h = pcg_hash(x ^ pcg_hash(y ^ pcg_hash(seed)));
    return f32(h >> 8u) * (1.0 / 16777216.0);
}
