// Twin: crates/voxcast_core/src/trace.rs (`accumulate`, `project`) with `Marcher::march` as
// `trace`, trace/first.rs (`first`, `hit`) and volume.rs (`value_at`), with the same
// skipping (for Accumulate, leaps over empty 4³ bricks by their distance and invisible cells
// left out once the cells are uploaded — trace/skipping.rs and trace/lanes.rs — and empty 8³
// blocks before; blocks that cannot hold the First hit or beat the running Maximum/Minimum, by
// their value ranges — `skip.wgsl`; none changes a pixel) and without recording. One position
// at a time: the CPU's eight lanes are its own way to the same samples.
// GPU-only: `classified`, `classified_with`, `shaded` and `shaded_with` (a sample's
// classification, then its shading, which the core's marches write out where they use them:
// named once here, as the methods share them).
#define_import_path voxcast::trace

#import voxcast::bindings::{params, FLAGS, METHOD, CLASSIFICATION, SKIP_EMPTY}
#import voxcast::clip::clip_interval
#import voxcast::step::{StepPlan, plan_steps, sample_t, segment_length, jitter_fraction, first_index_from}
#import voxcast::sample::{sample, to_data, gradient, cell, no_data_at, value_and_gradient_in_cell}
#import voxcast::skip::{block_of, block_exit, block_range, exit_if_empty, brick_at, brick_distance, visible, leap_exit_at}
#import voxcast::transfer::lut_lookup
#import voxcast::classify::classify
#import voxcast::shade::shade
#import voxcast::composite::{correct_opacity, accumulate_front_to_back, accumulate_back_to_front, reaches, crossing_fraction, sum_to_value}

/// Whether a sample's value and gradient come from the lattice records (integer volumes, their
/// records uploaded): one read of the cell's 8 corners, the same numbers as `sample` and
/// `gradient`. As in the core, for trilinear reconstruction only.
const RECORDED: bool = (FLAGS & #{FLAG_RECORDS}u) != 0u && (FLAGS & #{FLAG_TRILINEAR}u) != 0u;

/// The value (data units) at voxel position pv.
fn value_at(pv: vec3<f32>) -> f32 {
    return to_data(sample(pv));
}

/// Colour and classified opacity of value v at pv.
fn classified(v: f32, pv: vec3<f32>) -> vec4<f32> {
    let rgba = lut_lookup(v);
    if CLASSIFICATION == #{CLASSIFY_TABLE}u {
        return rgba;
    }
    return vec4(rgba.rgb, classify(v, rgba.a, length(gradient(pv))));
}

/// `classified`, with the gradient at the sample already read.
fn classified_with(v: f32, grad: vec3<f32>) -> vec4<f32> {
    let rgba = lut_lookup(v);
    if CLASSIFICATION == #{CLASSIFY_TABLE}u {
        return rgba;
    }
    return vec4(rgba.rgb, classify(v, rgba.a, length(grad)));
}

/// Shades colour c at pv if shading is on.
fn shaded(c: vec3<f32>, pv: vec3<f32>, view: vec3<f32>) -> vec3<f32> {
    if (FLAGS & #{FLAG_SHADING}u) == 0u {
        return c;
    }
    return shade(c, gradient(pv), pv * params.spacing, view);
}

/// `shaded`, with the gradient at the sample already read.
fn shaded_with(c: vec3<f32>, grad: vec3<f32>, pv: vec3<f32>, view: vec3<f32>) -> vec3<f32> {
    if (FLAGS & #{FLAG_SHADING}u) == 0u {
        return c;
    }
    return shade(c, grad, pv * params.spacing, view);
}

/// One ray through the volume: premultiplied colour (rgb) and opacity (a), before the
/// background. `t_max` stops the ray at opaque scene geometry; `pixel` keys the jitter.
fn trace(origin: vec3<f32>, dir: vec3<f32>, t_max: f32, pixel: vec2<u32>) -> vec4<f32> {
    let hit = clip_interval(origin, dir, 0.0, t_max);
    if !hit.hit {
        return vec4(0.0);
    }
    var jitter = 0.0;
    if (FLAGS & #{FLAG_JITTER}u) != 0u {
        jitter = jitter_fraction(pixel.x, pixel.y, params.jitter_seed);
    }
    let plan = plan_steps(hit.t_enter, hit.t_exit, params.dt, jitter, params.max_samples);
    let o_v = origin * params.inv_spacing;
    let d_v = dir * params.inv_spacing;
    let view = -dir;
    if METHOD == #{METHOD_ACCUMULATE}u {
        return accumulate(plan, o_v, d_v, view);
    }
    if METHOD == #{METHOD_FIRST}u {
        return first(plan, o_v, d_v, view);
    }
    if METHOD == #{METHOD_AVERAGE}u || METHOD == #{METHOD_MAXIMUM}u
        || METHOD == #{METHOD_MINIMUM}u || METHOD == #{METHOD_SUM}u {
        return project(plan, o_v, d_v);
    }
    // A method code no branch names: magenta, which no method draws, instead of passing for
    // another method (shaders.rs tests that every method has its branch).
    return vec4(1.0, 0.0, 1.0, 1.0);
}

fn accumulate(plan: StepPlan, o_v: vec3<f32>, d_v: vec3<f32>, view: vec3<f32>) -> vec4<f32> {
    let back_to_front = (FLAGS & #{FLAG_BACK_TO_FRONT}u) != 0u;
    var stop_at = 3.4e38;
    if (FLAGS & #{FLAG_EARLY_TERMINATION}u) != 0u && !back_to_front {
        stop_at = params.cutoff;
    }
    var acc = vec4(0.0);
    let skip = SKIP_EMPTY != 0u && !back_to_front;
    let leaping = (FLAGS & #{FLAG_SKIP_CELLS}u) != 0u;
    let margin_t = params.skip_margin / length(d_v);
    var checked = vec3(0xffffffffu);
    var i = 0u;
    loop {
        // The next sample to read (k, at t and pv): empty space and hidden cells are passed in
        // this inner loop, which reads no values, so that the reading, classifying and shading
        // below run once per sample read — not once per sample passed (a GPU that runs a
        // group's lanes in step pays for the code of every branch any lane takes).
        var found = false;
        var k = 0u;
        var t = 0.0;
        var pv = vec3(0.0);
        while i < plan.count {
            k = i;
            if back_to_front {
                k = plan.count - 1u - i;
            }
            t = sample_t(plan, k);
            pv = o_v + d_v * t;
            if skip && leaping {
                // The core's leaps (skip.rs, `VisibleCells`): out of the cube of empty bricks
                // around an empty one; in the others, only the cells the table can show.
                let lo = cell(pv).lo;
                let brick = brick_at(lo);
                let distance = brick_distance(brick);
                if distance > 0u {
                    i = max(i + 1u, first_index_from(plan, leap_exit_at(lo, distance, o_v, d_v)));
                    continue;
                }
                i += 1u;
                if !visible(lo, brick) {
                    continue;
                }
            } else {
                if skip {
                    // Before the cells are uploaded: leave an empty 8³ block at once.
                    let b = block_of(cell(pv).lo);
                    if any(b != checked) {
                        checked = b;
                        let t_out = exit_if_empty(b, o_v, d_v);
                        if t_out >= 0.0 {
                            let next = ceil((t_out - margin_t - plan.t_enter) / plan.dt - plan.jitter);
                            if next > f32(k) {
                                i = select(u32(next), plan.count, next >= f32(plan.count));
                                continue;
                            }
                        }
                    }
                }
                i += 1u;
            }
            found = true;
            break;
        }
        if !found {
            break;
        }
        if no_data_at(pv) {
            continue; // no data: transparent
        }
        // With the lattice records uploaded (integer volumes), the value and the gradient come
        // from one read of the cell's 8 corners, as in the core.
        var v: f32;
        var grad = vec3(0.0);
        if RECORDED {
            let vg = value_and_gradient_in_cell(cell(pv));
            v = to_data(vg.w);
            grad = vg.xyz;
        } else {
            v = value_at(pv);
        }
        var cl: vec4<f32>;
        if RECORDED {
            cl = classified_with(v, grad);
        } else {
            cl = classified(v, pv);
        }
        if cl.a <= 0.0 {
            continue;
        }
        var alpha = cl.a;
        if (FLAGS & #{FLAG_OPACITY_CORRECTION}u) != 0u {
            alpha = correct_opacity(cl.a, segment_length(plan, k, t), params.dt_ref);
        }
        if alpha > 0.0 {
            var color: vec3<f32>;
            if RECORDED {
                color = shaded_with(cl.rgb, grad, pv, view);
            } else {
                color = shaded(cl.rgb, pv, view);
            }
            if back_to_front {
                acc = accumulate_back_to_front(acc, color, alpha);
            } else {
                acc = accumulate_front_to_back(acc, color, alpha);
            }
        }
        if acc.a >= stop_at {
            break;
        }
    }
    return acc;
}

fn project(plan: StepPlan, o_v: vec3<f32>, d_v: vec3<f32>) -> vec4<f32> {
    if plan.count == 0u {
        return vec4(0.0);
    }
    let maximum = METHOD == #{METHOD_MAXIMUM}u;
    let extreme = maximum || METHOD == #{METHOD_MINIMUM}u;
    // The CPU's block skipping for Maximum and Minimum (trace/skipping.rs,
    // `project_extreme`): a block whose range cannot beat the running extreme is passed
    // without sampling.
    let skip = params.skip_ranges != 0u && extreme;
    let ties = params.ties_skippable != 0u;
    let margin_t = params.skip_margin / length(d_v);
    var checked = vec3(0xffffffffu);
    var sum = 0.0;
    var hi = -3.4e38;
    var lo = 3.4e38;
    // Samples with a value (those with no data are left out, as the core's statistics do).
    var counted = 0u;
    var k = 0u;
    while k < plan.count {
        let pv = o_v + d_v * sample_t(plan, k);
        if skip && counted > 0u {
            let b = block_of(cell(pv).lo);
            if any(b != checked) {
                checked = b;
                let r = block_range(b);
                var useless = r.x > lo || (ties && r.x == lo);
                if maximum {
                    useless = r.y < hi || (ties && r.y == hi);
                }
                if useless {
                    let next = first_index_from(plan, block_exit(b, o_v, d_v) - margin_t);
                    if next > k {
                        k = next;
                        continue;
                    }
                }
            }
        }
        k += 1u;
        if no_data_at(pv) {
            continue;
        }
        let v = value_at(pv);
        sum += v;
        hi = max(hi, v);
        lo = min(lo, v);
        counted += 1u;
    }
    if counted == 0u {
        return vec4(0.0);
    }
    // Average unless another projection (trace() sends only these four here).
    var value = sum / f32(counted);
    if maximum {
        value = hi;
    } else if extreme {
        value = lo;
    } else if METHOD == #{METHOD_SUM}u {
        // Σv·Δs with Δs the step in voxels along this ray, stretched over the table.
        let table_hi = params.lut_lo + f32(#{LUT_SIZE}u - 1u) / params.lut_scale;
        value = sum_to_value(
            sum * params.dt * length(d_v),
            vec2(params.sum_lo, params.sum_hi),
            vec2(params.lut_lo, table_hi),
        );
    }
    let rgba = lut_lookup(value);
    return vec4(rgba.rgb * rgba.a, rgba.a);
}

fn first(plan: StepPlan, o_v: vec3<f32>, d_v: vec3<f32>, view: vec3<f32>) -> vec4<f32> {
    let target_value = params.target_value;
    // The CPU's block skipping for First (trace/skipping.rs, `first_skipping`): a block
    // whose values all lie below the target holds no hit; only its last sample is read, as
    // the previous sample (the lower end of a later hit's bracket).
    let skip = params.skip_ranges != 0u;
    let margin_t = params.skip_margin / length(d_v);
    var checked = vec3(0xffffffffu);
    var have_prev = false;
    var prev_t = 0.0;
    var prev_v = 0.0;
    var k = 0u;
    while k < plan.count {
        let t = sample_t(plan, k);
        let pv = o_v + d_v * t;
        if skip {
            let b = block_of(cell(pv).lo);
            if any(b != checked) {
                checked = b;
                let r = block_range(b);
                if r.y < target_value {
                    let next = first_index_from(plan, block_exit(b, o_v, d_v) - margin_t);
                    if next > k {
                        prev_t = sample_t(plan, next - 1u);
                        let p_prev = o_v + d_v * prev_t;
                        prev_v = value_at(p_prev);
                        have_prev = !no_data_at(p_prev);
                        k = next;
                        continue;
                    }
                }
            }
        }
        if no_data_at(pv) {
            // No data: never a hit, and no lower end for a hit's bracket.
            have_prev = false;
            k += 1u;
            continue;
        }
        let v = value_at(pv);
        if reaches(v, target_value) {
            // The value rose past the target since the previous sample; or, at the first
            // sample, the ray enters the volume at or above it and hits right there.
            var ta = t;
            var va = v;
            if have_prev {
                ta = prev_t;
                va = prev_v;
            }
            return hit(ta, va, t, v, o_v, d_v, view);
        }
        prev_t = t;
        prev_v = v;
        have_prev = true;
        k += 1u;
    }
    return vec4(0.0);
}

/// Refines the hit in [ta, tb] (below the target at ta, at or above it at tb; one point when
/// the ray entered at or above it) by bisection then linear interpolation, and shades it.
fn hit(ta_in: f32, va_in: f32, tb_in: f32, vb_in: f32, o_v: vec3<f32>, d_v: vec3<f32>, view: vec3<f32>) -> vec4<f32> {
    let target_value = params.target_value;
    var ta = ta_in;
    var va = va_in;
    var tb = tb_in;
    var vb = vb_in;
    if tb > ta {
        for (var i = 0u; i < params.refine_steps; i++) {
            let tm = 0.5 * (ta + tb);
            if no_data_at(o_v + d_v * tm) {
                break; // no data between the two samples: keep the bracket as it is
            }
            let vm = value_at(o_v + d_v * tm);
            if reaches(vm, target_value) {
                tb = tm;
                vb = vm;
            } else {
                ta = tm;
                va = vm;
            }
        }
    }
    let t = ta + (tb - ta) * crossing_fraction(va, vb, target_value);
    let pv = o_v + d_v * t;
    let rgba = lut_lookup(target_value);
    // As in accumulate(): with the records, the gradient from one read of the cell's 8 corners.
    var color: vec3<f32>;
    if RECORDED {
        color = shaded_with(rgba.rgb, value_and_gradient_in_cell(cell(pv)).xyz, pv, view);
    } else {
        color = shaded(rgba.rgb, pv, view);
    }
    return vec4(color * rgba.a, rgba.a);
}
