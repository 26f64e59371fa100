//! The frame's unordered conflicts: pairs of the sandbox's systems that touch the same data
//! (one of them writing it) with no order between them, so that which runs first is up to
//! the scheduler. Bevy finds them as it builds a schedule (its ambiguity detection); the
//! play-through writes the sandbox's own beside its report (`ambiguities.txt`), and the levels'
//! test holds each to an explanation in `tests/data/ambiguities.txt`.

use bevy::ecs::schedule::{InternedScheduleLabel, ScheduleLabel, Schedules};
use bevy::prelude::*;

/// The schedules the sandbox's systems run in.
fn schedules() -> [(InternedScheduleLabel, &'static str); 3] {
    [
        (Update.intern(), "Update"),
        (PostUpdate.intern(), "PostUpdate"),
        (bevy_egui::EguiPrimaryContextPass.intern(), "egui pass"),
    ]
}

/// A system's name without its crate's path: `voxcast::sandbox::ui::settings::settings_panel`
/// becomes `ui::settings::settings_panel`; `None` for a system not the sandbox's.
fn ours(name: &str) -> Option<String> {
    let name = name.strip_prefix("voxcast::sandbox::")?;
    // A chained or piped system's name carries its generic arguments: keep the path.
    Some(name.split('<').next().unwrap_or(name).to_string())
}

/// Every unordered conflict between two of the sandbox's systems in the built schedules, one
/// line each — `schedule: a × b (data)`, the two names sorted — sorted and without repeats.
pub fn conflicts(world: &World) -> Vec<String> {
    let Some(all) = world.get_resource::<Schedules>() else {
        return Vec::new();
    };
    let mut lines = Vec::new();
    for (label, words) in schedules() {
        let Some(schedule) = all.get(label) else {
            continue;
        };
        // Built, a schedule keeps its systems in its executable part, not in its graph.
        let Ok(systems) = schedule.systems() else {
            continue;
        };
        let names: std::collections::HashMap<_, _> = systems
            .map(|(key, system)| (key, system.name().to_string()))
            .collect();
        for (a, b, data) in schedule.graph().conflicting_systems().iter() {
            let name = |k| names.get(k).and_then(|n: &String| ours(n));
            let (Some(a), Some(b)) = (name(a), name(b)) else {
                continue;
            };
            let (a, b) = if a <= b { (a, b) } else { (b, a) };
            // Each datum by its type's own name (`Messages<KeepDrawing>` as `KeepDrawing`).
            let mut data: Vec<String> = data
                .iter()
                .filter_map(|id| world.components().get_name(*id))
                .map(|d| {
                    let d = d.to_string();
                    let short = d.rsplit("::").next().unwrap_or(&d);
                    short.trim_end_matches('>').to_string()
                })
                .collect();
            data.sort();
            let data = if data.is_empty() {
                "the whole world".to_string()
            } else {
                data.join(", ")
            };
            lines.push(format!("{words}: {a} × {b} ({data})"));
        }
    }
    lines.sort();
    lines.dedup();
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Resource, Default)]
    struct Shared(u32);

    fn first(mut s: ResMut<Shared>) {
        s.0 += 1;
    }

    fn second(mut s: ResMut<Shared>) {
        s.0 *= 2;
    }

    fn reader(_: Res<Shared>) {}

    /// Two writers with no order conflict; a chain does not; Bevy's own systems are left out.
    #[test]
    fn unordered_writers_of_one_resource_are_found_and_ordered_ones_are_not() {
        let mut app = App::new();
        app.init_resource::<Shared>()
            .add_systems(Update, (first, second))
            .add_systems(PostUpdate, (first, second).chain())
            .add_systems(PostUpdate, reader);
        app.update();
        let found = conflicts(app.world());
        // The test's systems live in `voxcast::sandbox::drivers::ambiguities::tests`.
        let pair = "drivers::ambiguities::tests::first × drivers::ambiguities::tests::second";
        assert!(
            found
                .iter()
                .any(|l| l.starts_with("Update: ") && l.contains(pair)),
            "{found:?}"
        );
        assert!(
            !found
                .iter()
                .any(|l| l.starts_with("PostUpdate: ") && l.contains(pair)),
            "chained: {found:?}"
        );
        assert!(
            found
                .iter()
                .any(|l| l.starts_with("PostUpdate: ") && l.contains("tests::reader")),
            "a reader beside a writer: {found:?}"
        );
        assert!(found.iter().all(|l| l.ends_with("(Shared)")), "{found:?}");
    }

    #[test]
    fn names_lose_the_crate_path_and_others_are_left_out() {
        assert_eq!(
            ours("voxcast::sandbox::ui::settings::settings_panel").as_deref(),
            Some("ui::settings::settings_panel")
        );
        assert_eq!(ours("bevy_render::view::visibility"), None);
    }
}
