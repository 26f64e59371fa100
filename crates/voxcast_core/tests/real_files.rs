//! The files beside the clone that a machine may lack, read when they are there and reported
//! as ignored when not: the real volumes of `../shared/data` (or `VOXCAST_DATA`) load as they
//! are and their damaged copies fail cleanly; the presets made from the VTK peer's transfer
//! functions are those functions exactly, so Voxcast and VTK render the same inputs; every
//! peer transfer function and camera reads.

mod common;
mod support;

use support::{Completion, Outcome, data_dir, peer_dir};
use voxcast_core::builtin::load_builtin;
use voxcast_core::glam::{UVec3, Vec3};
use voxcast_core::io::load;
use voxcast_core::peer;
use voxcast_core::preset;
use voxcast_core::settings::RenderSettings;
use voxcast_core::volume::ScalarType;

fn main() {
    support::run(&[
        (
            "the_shared_real_volumes_load_as_they_are",
            the_shared_real_volumes_load_as_they_are,
        ),
        (
            "damaged_copies_of_the_shared_real_files_fail_cleanly",
            damaged_copies_of_the_shared_real_files_fail_cleanly,
        ),
        (
            "peer_derived_presets_equal_the_peer_files",
            peer_derived_presets_equal_the_peer_files,
        ),
        (
            "every_peer_transfer_function_and_camera_reads",
            every_peer_transfer_function_and_camera_reads,
        ),
    ])
}

fn the_shared_real_volumes_load_as_they_are() -> Outcome {
    let dir = match data_dir() {
        Ok(d) => d,
        Err(skip) => return skip,
    };
    let ct = load(&dir.join("ct_cranium.nrrd")).unwrap().volume;
    assert_eq!(ct.dims(), UVec3::new(256, 256, 108));
    assert_eq!(ct.scalar_type(), ScalarType::I16);
    assert!(
        (ct.spacing() - Vec3::new(0.9570312, 0.9570312, 1.5))
            .abs()
            .max_element()
            < 1e-6
    );
    assert_eq!(ct.value_range(), (-1024.0, 2986.0));
    let mni = load(&dir.join("mri_mni152.nii.gz")).unwrap().volume;
    assert_eq!(
        (mni.dims(), mni.scalar_type()),
        (UVec3::new(197, 233, 189), ScalarType::U8)
    );
    assert_eq!(mni.spacing(), Vec3::ONE);
    let brain = load(&dir.join("mri_brainsmall.nrrd")).unwrap().volume;
    assert_eq!(
        (brain.dims(), brain.value_range()),
        (UVec3::new(128, 128, 84), (0.0, 202.0))
    );
    let bunny = load(&dir.join("bunny_sdf.nrrd")).unwrap().volume;
    assert_eq!(bunny.dims(), UVec3::new(128, 126, 101));
    // The embedded copies are the same data.
    assert_eq!(
        load_builtin("brainsmall").unwrap().volume.data(),
        brain.data()
    );
    assert_eq!(load_builtin("bunny").unwrap().volume.data(), bunny.data());
    Ok(Completion::Completed)
}

fn damaged_copies_of_the_shared_real_files_fail_cleanly() -> Outcome {
    let dir = match data_dir() {
        Ok(d) => d,
        Err(skip) => return skip,
    };
    common::damaged_copies_fail_cleanly(
        ["ct_cranium.nrrd", "mri_mni152.nii.gz"]
            .iter()
            .map(|name| (name.to_string(), std::fs::read(dir.join(name)).unwrap()))
            .collect(),
    );
    Ok(Completion::Completed)
}

fn peer_derived_presets_equal_the_peer_files() -> Outcome {
    let dir = match peer_dir() {
        Ok(d) => d.join("tf"),
        Err(skip) => return skip,
    };
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
    Ok(Completion::Completed)
}

fn every_peer_transfer_function_and_camera_reads() -> Outcome {
    let dir = match peer_dir() {
        Ok(d) => d,
        Err(skip) => return skip,
    };
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
    Ok(Completion::Completed)
}
