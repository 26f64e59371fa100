// Twin: crates/voxcast_core/src/classify.rs (`iso_contour_alpha`, `Classifier::classify`,
// `Region::contains`).
#define_import_path voxcast::classify

#import voxcast::bindings::{params, CLASSIFICATION}

/// One isovalue's contour opacity (Levoy 1988) for value f with gradient magnitude g.
fn iso_contour_alpha(f: f32, g: f32, f_v: f32, alpha_v: f32, r: f32) -> f32 {
    let d = abs(f_v - f);
    if g <= 0.0 {
        return select(0.0, alpha_v, d == 0.0);
    }
    if d <= r * g {
        return alpha_v * (1.0 - d / (r * g));
    }
    return 0.0;
}

/// Whether (f, g) lies in rectangle i of the value-and-gradient classification (edges in).
fn contains(i: u32, f: f32, g: f32) -> bool {
    let r = params.regions[i];
    return f >= r.x && f <= r.y && g >= r.z && g <= r.w;
}

/// Opacity for value f with table opacity table_alpha and gradient magnitude g.
fn classify(f: f32, table_alpha: f32, g: f32) -> f32 {
    if CLASSIFICATION == #{CLASSIFY_ISO_CONTOURS}u {
        var transparency = 1.0;
        for (var i = 0u; i < params.iso_count; i++) {
            transparency *= 1.0 - iso_contour_alpha(f, g, params.iso_values[i], params.iso_alphas[i], params.iso_r);
        }
        return 1.0 - transparency;
    }
    if CLASSIFICATION == #{CLASSIFY_BOUNDARIES}u {
        return min(table_alpha * g * params.inv_full_gradient, 1.0);
    }
    if CLASSIFICATION == #{CLASSIFY_VALUE_GRADIENT}u {
        var alpha = 0.0;
        for (var i = 0u; i < params.region_count; i++) {
            if contains(i, f, g) {
                alpha = max(alpha, params.region_opacity[i]);
            }
        }
        return alpha;
    }
    return table_alpha;
}
