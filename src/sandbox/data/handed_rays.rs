//! A `.rayvis` file handed over by the browser (a page has no paths): kept, chosen in the Ray
//! data section and its density computed.

use crate::sandbox::data::choices::RayChoices;
use crate::sandbox::data::estimate::Estimator;
use crate::sandbox::data::loading::Loading;
use crate::sandbox::data::source::SourceKind;
use crate::sandbox::shared::files::{FilesChosen, Purpose};
use crate::sandbox::shared::schedule::Frame;
use bevy::prelude::*;

pub(crate) fn plugin(app: &mut App) {
    app.add_message::<FilesChosen>()
        .add_systems(Update, take_chosen_rays.in_set(Frame::Input));
}

/// A `.rayvis` file the browser handed over (a page has no paths): kept under its name, chosen
/// as the Ray data section's file with every trace, and its density computed at once, as a
/// volume file opens at once.
fn take_chosen_rays(
    mut chosen: MessageReader<FilesChosen>,
    mut choices: ResMut<RayChoices>,
    mut estimator: ResMut<Estimator>,
    mut loading: ResMut<Loading>,
) {
    for FilesChosen { purpose, files } in chosen.read() {
        let Some((name, bytes)) = files.first().filter(|_| *purpose == Purpose::Rays) else {
            continue;
        };
        voxcast_core::rays::source::hand_over(name, bytes.clone());
        estimator.forget(name);
        choices.source = SourceKind::File;
        choices.path = name.clone();
        choices.trace = None;
        if let Some(spec) = choices.spec() {
            loading.start_keeping_choices(spec.to_text());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sandbox::shared::state::VolumeState;

    /// A `.rayvis` file a page hands over becomes the Ray data section's file and its density
    /// is computed at once, as a path's is on the desktop.
    #[test]
    fn a_handed_rayvis_file_is_computed_at_once() {
        let mut app = crate::sandbox::data::loading::tests::app();
        app.add_plugins((
            crate::sandbox::data::choices::plugin,
            crate::sandbox::data::estimate::plugin,
            plugin,
        ));
        let bytes = include_bytes!("../../../tests/data/two_level.rayvis").to_vec();
        app.world_mut().write_message(FilesChosen {
            purpose: Purpose::Rays,
            files: vec![("handed in a page.rayvis".into(), bytes)],
        });
        crate::sandbox::data::loading::tests::run_until_idle(&mut app);
        let world = app.world();
        assert_eq!(world.resource::<Loading>().error, None);
        let source = &world.resource::<VolumeState>().source;
        assert!(
            source.starts_with("density:handed in a page.rayvis"),
            "{source}"
        );
        let choices = world.resource::<RayChoices>();
        assert_eq!(choices.path, "handed in a page.rayvis");
        assert_eq!(
            choices.source,
            crate::sandbox::data::source::SourceKind::File
        );
    }
}
