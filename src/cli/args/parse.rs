//! The values a user types on the command line (or a page's query string), parsed into the
//! core's types with errors that say what was expected.

use super::CliError;
use voxcast_core::classify::Classification;
use voxcast_core::clip::ClipPlane;
use voxcast_core::composite::Method;
use voxcast_core::glam::Vec3;
use voxcast_core::shade::{Light, LightSource, Spot};
use voxcast_core::tunables as t;

/// `table`, `iso:V1,V2[@R]`, `boundaries[@G]`, `rects:F0,F1,G0,G1@A[/…]`.
pub(super) fn parse_classification(s: &str) -> Result<Classification, CliError> {
    let bad = || {
        CliError::usage(format!(
            "--classify '{s}': expected table, iso:V1,V2,…[@THICKNESS], boundaries[@GRADIENT] \
             or rects:F0,F1,G0,G1@OPACITY[/F0,F1,G0,G1@OPACITY…]"
        ))
    };
    if let Some(rects) = s.strip_prefix("rects:") {
        let regions = rects
            .split('/')
            .map(|r| {
                let (bounds, opacity) = r.split_once('@')?;
                let v: Vec<f32> = bounds
                    .split(',')
                    .map(|x| x.trim().parse::<f32>().ok())
                    .collect::<Option<_>>()?;
                let [f0, f1, g0, g1]: [f32; 4] = v.try_into().ok()?;
                Some(voxcast_core::classify::Region {
                    value: [f0, f1],
                    gradient: [g0, g1],
                    opacity: opacity.trim().parse().ok()?,
                })
            })
            .collect::<Option<Vec<_>>>()
            .ok_or_else(bad)?;
        return Ok(Classification::ValueGradient { regions });
    }
    let (head, at) = match s.split_once('@') {
        Some((h, a)) => (h, Some(a.parse::<f32>().map_err(|_| bad())?)),
        None => (s, None),
    };
    if head == "table" {
        return Ok(Classification::Table);
    }
    if head == "boundaries" {
        return Ok(Classification::Boundaries { full_gradient: at });
    }
    if let Some(values) = head.strip_prefix("iso:") {
        let isovalues = values
            .split(',')
            .map(|v| v.trim().parse::<f32>())
            .collect::<Result<Vec<_>, _>>()
            .map_err(|_| bad())?;
        return Ok(Classification::IsoContours {
            isovalues,
            thickness_voxels: at.unwrap_or(t::ISO_THICKNESS.default),
        });
    }
    Err(bad())
}

/// `x,y,z` → Vec3.
/// `--crop`: six numbers, lower and upper side per axis.
pub(super) fn parse_crop(s: &str) -> Result<(Vec3, Vec3), String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{s}': expected six numbers x0,x1,y0,y1,z0,z1"))?;
    let [x0, x1, y0, y1, z0, z1]: [f32; 6] = v
        .try_into()
        .map_err(|_| format!("'{s}': expected six numbers x0,x1,y0,y1,z0,z1"))?;
    Ok((Vec3::new(x0, y0, z0), Vec3::new(x1, y1, z1)))
}

/// `--clip-plane`: a normal and an optional position after `@`.
pub(super) fn parse_clip_plane(s: &str) -> Result<ClipPlane, String> {
    let (normal, position) = match s.split_once('@') {
        Some((n, p)) => (
            n,
            p.trim()
                .parse::<f32>()
                .map_err(|_| format!("'{s}': the position after @ must be a number"))?,
        ),
        None => (s, 0.0),
    };
    Ok(ClipPlane {
        normal: parse_vec3(normal)?,
        position,
    })
}

/// `LOW,HIGH`: two finite numbers, the first below the second.
pub fn parse_range(s: &str) -> Result<(f32, f32), String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{s}': expected two numbers low,high"))?;
    match v[..] {
        [a, b] if a.is_finite() && b.is_finite() && a < b => Ok((a, b)),
        [_, _] => Err(format!("'{s}': two finite numbers, the low one first")),
        _ => Err(format!("'{s}': expected two numbers low,high")),
    }
}

pub fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{s}': expected three numbers x,y,z"))?;
    let a: [f32; 3] = v
        .try_into()
        .map_err(|_| format!("'{s}': expected three numbers x,y,z"))?;
    let v = Vec3::from(a);
    if !v.is_finite() {
        return Err(format!("'{s}': numbers must be finite"));
    }
    Ok(v)
}

/// `--method`: the five methods by name (and `mip` for maximum), each listed in `--help`
/// with its one-line description (the sandbox's tooltip).
pub(super) fn method_parser() -> impl clap::builder::TypedValueParser<Value = Method> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    PossibleValuesParser::new(
        Method::ALL
            .map(|m| PossibleValue::new(m.name()).help(m.doc()))
            .into_iter()
            .chain([PossibleValue::new("mip").hide(true)]),
    )
    .map(|s| Method::parse(&s).expect("a possible value"))
}

/// One `--light`: `none` (no light at all), or a place and an optional `@R,G,B` colour.
pub(super) fn parse_light(s: &str) -> Result<Option<LightSource>, String> {
    if s == "none" {
        return Ok(None);
    }
    let (place, color) = match s.split_once('@') {
        Some((place, color)) => (place, Some(color)),
        None => (s, None),
    };
    let light = if place == "headlight" {
        Light::Headlight
    } else if let Some(p) = place.strip_prefix("point:") {
        Light::Point(parse_vec3(p)?)
    } else if let Some(d) = place.strip_prefix("dir:") {
        let v = parse_vec3(d)?;
        if v.length_squared() == 0.0 {
            return Err("dir:0,0,0 is not a direction".into());
        }
        Light::Directional(v)
    } else if let Some(spot) = place.strip_prefix("spot:") {
        let Some((at, along)) = spot.split_once('>') else {
            return Err(format!(
                "'{s}': a spot is spot:X,Y,Z>DX,DY,DZ (where, then along)"
            ));
        };
        let direction = parse_vec3(along)?;
        if direction.length_squared() == 0.0 {
            return Err(format!("'{s}': a spot's direction cannot be 0,0,0"));
        }
        Light::Spot(Spot {
            position: parse_vec3(at)?,
            direction,
            ..Spot::default()
        })
    } else {
        return Err(format!(
            "'{s}': expected none, headlight, point:X,Y,Z, dir:X,Y,Z or spot:X,Y,Z>DX,DY,DZ, \
             optionally @R,G,B"
        ));
    };
    let mut source = LightSource::new(light);
    if let Some(c) = color {
        let c = parse_vec3(c)?;
        if c.min_element() < 0.0 {
            return Err(format!("light colour {c} has a negative channel"));
        }
        source.color = c;
    }
    Ok(Some(source))
}

/// `WxH` → (w, h).
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}': expected WIDTHxHEIGHT"))?;
    let w: u32 = w
        .parse()
        .map_err(|_| format!("'{s}': width is not a whole number"))?;
    let h: u32 = h
        .parse()
        .map_err(|_| format!("'{s}': height is not a whole number"))?;
    voxcast_core::render::validate_size(w, h).map_err(|e| e.to_string())?;
    Ok((w, h))
}

/// The page's own options, which its loader reads (`gpu`: which build to start; `fallback`:
/// which build stopped drawing before it, `web/voxcast.js`).
#[cfg(any(test, target_arch = "wasm32"))]
pub(super) const PAGE_ONLY: [&str; 2] = ["gpu", "fallback"];

/// A web page's query string as command-line options: `?a=1&b` → `["--a", "1", "--b"]`, each
/// part decoded by `decode` (`+` is a space, as forms write it); the page's own left out.
#[cfg(any(test, target_arch = "wasm32"))]
pub fn query_to_args(search: &str, decode: impl Fn(&str) -> String) -> Vec<String> {
    let mut args = Vec::new();
    for part in search.trim_start_matches('?').split('&') {
        if part.is_empty() {
            continue;
        }
        let (key, value) = match part.split_once('=') {
            Some((k, v)) => (k, Some(v)),
            None => (part, None),
        };
        if PAGE_ONLY.contains(&key) {
            continue;
        }
        args.push(format!("--{}", decode(&key.replace('+', " "))));
        // `no-rays=` (as a browser's URLSearchParams writes a flag back) is the flag alone.
        if let Some(v) = value.filter(|v| !v.is_empty()) {
            args.push(decode(&v.replace('+', " ")));
        }
    }
    args
}
