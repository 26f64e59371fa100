//! The presets made from the VTK peer's transfer functions are those functions, exactly, so that
//! Voxcast and VTK render the same inputs (checked where `../shared/tools/peer` exists).

use std::path::Path;
use voxcast_core::peer;
use voxcast_core::preset;
use voxcast_core::settings::RenderSettings;

#[test]
fn peer_derived_presets_equal_the_peer_files() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/tools/peer/tf");
    if !dir.is_dir() {
        eprintln!(
            "note: {} not found; the peer comparison is not made in this run",
            dir.display()
        );
        return;
    }
    for name in ["ct_skin_bone", "mri_brain", "bunny"] {
        let text = std::fs::read_to_string(dir.join(format!("{name}.json"))).unwrap();
        let from_peer = peer::from_json(&text).unwrap();
        let ours = preset::by_name(name).unwrap();
        let (a, b) = (from_peer.transfer.points(), ours.transfer.points());
        assert_eq!(a.len(), b.len(), "{name}");
        for (p, q) in a.iter().zip(b) {
            assert_eq!(p.value, q.value, "{name}");
            assert!((p.alpha - q.alpha).abs() < 1e-6, "{name} at {}", p.value);
            for c in 0..3 {
                assert!(
                    (p.color[c] - q.color[c]).abs() < 1e-6,
                    "{name} at {}",
                    p.value
                );
            }
        }
        let mut expected = RenderSettings::default();
        from_peer.apply(&mut expected);
        let got = ours.settings_over(&RenderSettings::default()).unwrap();
        assert_eq!(got.shading, expected.shading, "{name}");
        assert_eq!(got.phong.ka, expected.phong.ka, "{name}");
        assert_eq!(got.phong.kd, expected.phong.kd, "{name}");
        assert_eq!(got.phong.ks, expected.phong.ks, "{name}");
        assert_eq!(got.phong.shininess, expected.phong.shininess, "{name}");
        assert_eq!(got.reference_step, expected.reference_step, "{name}");
    }
}

#[test]
fn every_peer_transfer_function_and_camera_reads() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/tools/peer");
    if !dir.is_dir() {
        eprintln!(
            "note: {} not found; the peer's files are not read in this run",
            dir.display()
        );
        return;
    }
    let mut seen = 0;
    for sub in ["tf", "cams"] {
        for entry in std::fs::read_dir(dir.join(sub)).unwrap() {
            let path = entry.unwrap().path();
            let text = std::fs::read_to_string(&path).unwrap();
            if sub == "tf" {
                assert!(peer::is_peer_json(&text), "{}", path.display());
                peer::from_json(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            } else {
                voxcast_core::camera::Camera::from_json(&text)
                    .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            }
            seen += 1;
        }
    }
    assert!(
        seen >= 17,
        "13 transfer functions and 4 cameras, found {seen}"
    );
}
