//! One sample's shading with its own numbers put in: the model in symbols (Voxcast's shortened
//! form, or the lecture's full one when any of its further terms is on), then every term that
//! is on as `name = expression = result`, each light's falloff and spotlight factor, and the
//! sum before and after the clamp — the breakdown panel shows it, a test recomputes it.

use crate::numbers::{sig, sig3};
use crate::shade::{Highlight, LightTerms, ShadeTerms};

/// The shading of a sample whose transfer-function colour is `c` and whose shaded colour is
/// `shaded`, one equation a line.
pub fn shading(t: &ShadeTerms, c: [f32; 3], shaded: [f32; 3]) -> String {
    if !t.lit {
        return "shading: the gradient is too small here to give a normal, so the sample keeps \
                its colour"
            .into();
    }
    let k = &t.k;
    let full = t.full_form();
    let mut out = vec![format!(
        "shading, normal N = {}, {}:",
        sig3(t.normal),
        if full {
            "the lecture's full model: colour = M_e + G_a·M_a + Σ_i f_i·s_i·[I_a,i·M_a + \
             I_i·M_d·max(N·L_i, 0) + I_i·M_s·spec_i] with M_e = ke·c, M_a = ka·c, M_d = kd·c, \
             M_s = ks·h"
        } else {
            "Voxcast's shortened form: colour = ka·c + Σ_i f_i·I_i·(kd·max(N·L_i, 0)·c + \
             ks·spec_i·h)"
        }
    )];
    out.push(match t.highlight {
        Highlight::White => "h = 1: a white highlight (OpenGL, VTK)".into(),
        Highlight::Levoy => format!(
            "h = c = {}: Levoy's highlight, tinted by the sample's colour",
            sig3(t.tint)
        ),
    });
    if k.ke != 0.0 {
        out.push(format!(
            "emission M_e = ke·c = {}·{} = {}",
            sig(k.ke),
            sig3(c),
            sig3(t.emission)
        ));
    }
    out.push(if k.ga != 1.0 {
        format!(
            "ambient G_a·ka·c = {}·{}·{} = {}",
            sig(k.ga),
            sig(k.ka),
            sig3(c),
            sig3(t.ambient)
        )
    } else {
        format!(
            "ambient ka·c = {}·{} = {}",
            sig(k.ka),
            sig3(c),
            sig3(t.ambient)
        )
    });
    for (i, l) in t.per_light().iter().enumerate() {
        light(&mut out, i + 1, l, t, c);
    }
    // The terms of the sum that are on, each with its name.
    let terms = [
        (k.ke != 0.0, "M_e", t.emission),
        (true, "ambient", t.ambient),
        (
            t.light_ambient != [0.0; 3],
            "Σ lights' ambient",
            t.light_ambient,
        ),
        (true, "Σ diffuse", t.diffuse),
        (true, "Σ specular", t.specular),
    ];
    let on = || terms.iter().filter(|(on, ..)| *on);
    let names: Vec<&str> = on().map(|(_, name, _)| *name).collect();
    let parts: Vec<String> = on().map(|(.., v)| sig3(*v)).collect();
    let sum: [f32; 3] = std::array::from_fn(|ch| {
        t.emission[ch] + t.ambient[ch] + t.light_ambient[ch] + t.diffuse[ch] + t.specular[ch]
    });
    out.push(format!(
        "sum {} = {} = {}",
        names.join(" + "),
        parts.join(" + "),
        sig3(sum)
    ));
    out.push(format!(
        "each channel clipped to [0, 1]: the shaded colour is {}",
        sig3(shaded)
    ));
    out.join("\n")
}

/// Light `n`'s lines: its falloff, spotlight factor and terms.
fn light(out: &mut Vec<String>, n: usize, l: &LightTerms, t: &ShadeTerms, c: [f32; 3]) {
    let k = &t.k;
    let f = if t.depth_cue {
        out.push(format!(
            "light {n}: d = {} from the picture plane; Levoy's depth cue f = 1/(k1 + k2·d) = \
             1/({} + {}·{}) = {}",
            sig(l.distance),
            sig(k.depth_k1),
            sig(k.depth_k2),
            sig(l.distance),
            sig(l.attenuation)
        ));
        "f·"
    } else if l.positional {
        out.push(format!(
            "light {n}: d = {} to the light; f = 1/(kc + kl·d + kq·d·d) = 1/({} + {}·{} + \
             {}·{}·{}) = {}",
            sig(l.distance),
            sig(l.kc),
            sig(l.kl),
            sig(l.distance),
            sig(l.kq),
            sig(l.distance),
            sig(l.distance),
            sig(l.attenuation)
        ));
        "f·"
    } else {
        ""
    };
    let s = if l.spotlight {
        out.push(format!(
            "light {n}: spotlight factor s = {} ({})",
            sig(l.spot),
            if l.spot > 0.0 {
                "inside the cone: (cos of the angle to its axis)^exponent"
            } else {
                "outside the cone"
            }
        ));
        "s·"
    } else {
        ""
    };
    // The factors in front: f and s where they apply.
    let front = |what: &str| {
        let mut v = Vec::new();
        if !f.is_empty() {
            v.push(sig(l.attenuation));
        }
        if !s.is_empty() {
            v.push(sig(l.spot));
        }
        v.push(what.to_string());
        v.join("·")
    };
    let i_light = sig3(l.color);
    if l.ambient_color != [0.0; 3] {
        out.push(format!(
            "light {n} ambient {f}{s}I_a·ka·c = {}·{}·{} = {}",
            front(&sig3(l.ambient_color)),
            sig(k.ka),
            sig3(c),
            sig3(l.ambient)
        ));
    }
    out.push(format!("light {n}: N·L = {}", sig(l.n_dot_l)));
    out.push(format!(
        "light {n} diffuse {f}{s}I·kd·max(N·L, 0)·c = {}·{}·{}·{} = {}",
        front(&i_light),
        sig(k.kd),
        sig(l.n_dot_l.max(0.0)),
        sig3(c),
        sig3(l.diffuse),
    ));
    out.push(format!(
        "light {n} specular {f}{s}I·ks·spec·h = {}·{}·{}·{} = {}",
        front(&i_light),
        sig(k.ks),
        sig(l.spec),
        sig3(t.tint),
        sig3(l.specular)
    ));
}
