//! The level editor's logic: a draft level made from the view on screen ("New level from this
//! view") or from a level in the list ("Edit this level"); steps added as snapshots of the
//! scene as it is (data set, settings, transfer function, the main and the virtual camera, the
//! selected ray), retaken, moved, deleted and played; the draft saved as a file (a download on
//! the page) and shared as a link. The window that edits the draft's words and objectives is
//! `ui/level_editor.rs`; it sends [`EditorCommand`]s, applied here where the scene is seen.

use super::*;
use crate::sandbox::shared::files;
use voxcast_core::camera::Projection;
use voxcast_core::level::{CameraPlace, LevelScene, Origin, StepScene, TransferChoice};

/// The draft being edited, and what the editor last said.
#[derive(Resource, Default)]
pub struct Draft {
    pub level: Option<Level>,
    /// The step selected in the editor.
    pub step: usize,
    /// Where Save writes (a file name on the page: the download's).
    pub file: String,
    pub message: Option<String>,
    /// The last link made (Copy link), shown to be copied by hand where no clipboard is.
    pub link: Option<String>,
    /// The situation when the selected step was chosen: what "met now" compares with for the
    /// objectives that ask for a change.
    pub baseline: Option<Situation>,
    /// The window is open.
    pub open: bool,
}

impl Draft {
    /// Whether the selected step's objective is met by what is on screen now (`None`: no
    /// step), judged as the level will judge it, against the state when the step was chosen.
    pub fn met_now(&self, now: &Situation) -> Option<bool> {
        let step = self.level.as_ref()?.steps.get(self.step)?;
        let sit = Situation {
            at_open: self.baseline.clone().map(Box::new),
            ..now.clone()
        };
        Some(step.objective.met(&sit))
    }
}

/// What the editor's window asks for.
#[derive(Message, Clone, Debug, PartialEq)]
pub enum EditorCommand {
    /// A new draft whose scene is the view on screen, with one step to read.
    NewFromView,
    /// The list's level `i` as the draft.
    Edit(usize),
    /// A step added after the selected one, its scene the view on screen.
    AddStep,
    /// Step `k`'s scene taken again from the view on screen.
    Retake(usize),
    /// Step `k` chosen (its "met now" judged from here).
    Select(usize),
    /// Step `k` moved up (−1) or down (+1).
    Move(usize, isize),
    /// Step `k` deleted (a level keeps at least one).
    Delete(usize),
    /// The draft played from step `k`, as a student plays it.
    Play(usize),
    /// The draft written to [`Draft::file`].
    Save,
    /// The draft's link made for the page at this address (without a fragment).
    CopyLink(String),
}

/// What the editor sees of the scene.
#[derive(bevy::ecs::system::SystemParam)]
pub(crate) struct Scene<'w, 's> {
    volume: Res<'w, VolumeState>,
    render: Res<'w, RenderState>,
    views: Query<'w, 's, &'static View, With<MainCamera>>,
    cameras: Query<'w, 's, &'static VirtualCamera>,
    selection: Res<'w, RaySelection>,
    preview: Option<Res<'w, PreviewSettings>>,
}

impl Scene<'_, '_> {
    /// The view on screen as a step's scene: every part, the transfer function and settings
    /// written out.
    fn snapshot(&self) -> StepScene {
        snapshot(
            &self.volume,
            &self.render,
            self.views.single().ok().map(|v| &v.0),
            self.cameras.single().ok(),
            self.selection.selected,
        )
    }
}

/// `volume`, `render`, the main camera, the virtual camera and the selected ray as a step's
/// scene (what "Add this view as a step" keeps).
pub fn snapshot(
    volume: &VolumeState,
    render: &RenderState,
    main: Option<&voxcast_core::camera::Camera>,
    vc: Option<&VirtualCamera>,
    ray: Option<UVec2>,
) -> StepScene {
    let place = |c: &voxcast_core::camera::Camera, pixels: Option<[u32; 2]>| CameraPlace {
        eye: c.eye.to_array(),
        target: c.target.to_array(),
        up: c.up.to_array(),
        fov_y_deg: match c.projection {
            Projection::Perspective { fov_y_deg } => Some(fov_y_deg),
            Projection::Orthographic { .. } => None,
        },
        pixels,
    };
    let settings = serde_json::to_value(&render.settings)
        .ok()
        .and_then(|mut v| {
            voxcast_core::level::shortest_f32s(&mut v);
            v.as_object().cloned()
        });
    StepScene {
        volume: Some(volume.source.clone()),
        // A preset's own transfer function by its name; one edited, written out.
        transfer: Some(match voxcast_core::preset::by_name(&render.transfer.name) {
            Some(p) if p.transfer == render.transfer => TransferChoice::Named(p.name),
            _ => TransferChoice::Inline(render.transfer.clone()),
        }),
        settings,
        camera: main.map(|c| place(c, None)),
        virtual_camera: vc.map(|v| place(&v.view, Some([v.width, v.height]))),
        ray: vc.and(ray).map(|p| [p.x, p.y]),
    }
}

/// A new level whose scene is `scene` (the view on screen), with one step to read.
fn new_level(scene: StepScene, preview: bool) -> Level {
    let pixels = scene.virtual_camera.and_then(|c| c.pixels);
    Level {
        schema: None,
        id: "my-level".into(),
        title: "My level".into(),
        concept: "What this level teaches, in a sentence.".into(),
        scene: LevelScene {
            volume: scene.volume.unwrap_or_else(|| "builtin:bunny".into()),
            preview,
            rays: pixels.map(|[w, h]| w.max(h)),
            light: true,
            panel: None,
            preset: None,
            transfer: scene.transfer,
            settings: scene.settings,
            camera: scene.camera,
            virtual_camera: scene.virtual_camera,
            ray: scene.ray,
            lecture_ray: false,
            preview_scale: None,
        },
        steps: vec![Step {
            text: "Look at the scene: what does it show?".into(),
            control: None,
            objective: Objective::Read,
            scene: None,
        }],
        origin: Origin::Embedded,
    }
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<Draft>()
        .add_message::<EditorCommand>()
        .add_systems(
            Update,
            apply_editor_commands
                .before(super::apply_commands)
                .in_set(crate::sandbox::shared::schedule::Frame::Rules),
        );
}

/// Carries out the editor window's commands on the draft.
fn apply_editor_commands(
    mut commands: MessageReader<EditorCommand>,
    mut draft: ResMut<Draft>,
    mut lessons: ResMut<Lessons>,
    scene: Scene,
    mut start: MessageWriter<LevelCommand>,
) {
    for command in commands.read() {
        let now = lessons.now.clone();
        let done = match command {
            EditorCommand::NewFromView => {
                let preview = scene.preview.as_ref().is_some_and(|p| p.enabled);
                draft.open_new(new_level(scene.snapshot(), preview));
                Some(())
            }
            EditorCommand::Edit(i) => lessons.levels.get(*i).map(|l| draft.open_level(l)),
            EditorCommand::AddStep => draft.add_step(scene.snapshot()),
            EditorCommand::Retake(k) => {
                draft.retake(*k, scene.snapshot());
                Some(())
            }
            EditorCommand::Select(k) => {
                draft.step = *k;
                Some(())
            }
            EditorCommand::Move(k, by) => draft.move_step(*k, *by),
            EditorCommand::Delete(k) => draft.delete_step(*k),
            EditorCommand::Play(k) => draft.level.clone().map(|level| {
                let i = lessons.keep_level(level);
                start.write(LevelCommand::StartAt(i, *k));
                draft.message = Some(
                    "Playing the draft as a student would; Edit this level brings it back.".into(),
                );
            }),
            EditorCommand::Save => draft.level.clone().map(|level| {
                draft.message = Some(save(&mut draft, level, &mut lessons));
            }),
            EditorCommand::CopyLink(page) => draft.copy_link(page),
        };
        // The step chosen now is judged from the scene as it is now.
        let judged = !matches!(command, EditorCommand::CopyLink(_) | EditorCommand::Save);
        if done.is_some() && judged {
            draft.baseline = Some(now);
        }
    }
}

/// What the editor's commands do to the draft; `None` where there is no draft level to do it
/// to.
impl Draft {
    /// Opens a new level in the editor.
    fn open_new(&mut self, level: Level) {
        self.level = Some(level);
        self.step = 0;
        self.file = "my-level.json".into();
        self.open = true;
        self.message = Some(
            "A new level from this view: write its words, then add a step for each view you \
             set up."
                .into(),
        );
    }

    /// Opens a copy of `level` in the editor, to be saved to its own file (or one named after
    /// its id).
    fn open_level(&mut self, level: &Level) {
        self.file = match &level.origin {
            Origin::File(p) => p.display().to_string(),
            _ => format!("{}.json", level.id),
        };
        self.level = Some(level.clone());
        self.step = 0;
        self.open = true;
        self.message = None;
    }

    /// A step after the chosen one, opening on `scene`; it becomes the chosen one.
    fn add_step(&mut self, scene: StepScene) -> Option<()> {
        let level = self.level.as_mut()?;
        let at = (self.step + 1).min(level.steps.len());
        level.steps.insert(
            at,
            Step {
                text: "What to do, and what the student will see.".into(),
                control: None,
                objective: Objective::Read,
                scene: Some(scene),
            },
        );
        self.step = at;
        Some(())
    }

    /// Step `k` opens on `scene` from now on.
    fn retake(&mut self, k: usize, scene: StepScene) {
        if let Some(step) = self.level.as_mut().and_then(|l| l.steps.get_mut(k)) {
            step.scene = Some(scene);
            self.message = Some(format!("Step {} now opens with this view.", k + 1));
        }
    }

    /// Step `k` swapped with the one `by` places away, where there is one.
    fn move_step(&mut self, k: usize, by: isize) -> Option<()> {
        let level = self.level.as_mut()?;
        if let Some(to) = k.checked_add_signed(by).filter(|&t| t < level.steps.len()) {
            level.steps.swap(k, to);
            self.step = to;
        }
        Some(())
    }

    /// Step `k` deleted, unless it is the last one.
    fn delete_step(&mut self, k: usize) -> Option<()> {
        let level = self.level.as_mut()?;
        if level.steps.len() > 1 && k < level.steps.len() {
            level.steps.remove(k);
            self.step = self.step.min(level.steps.len() - 1);
        } else {
            self.message = Some("A level keeps at least one step.".into());
        }
        Some(())
    }

    /// The level as a link to `page`, copied where a clipboard is reached and kept to show.
    fn copy_link(&mut self, page: &str) -> Option<()> {
        let level = self.level.as_ref()?;
        match voxcast_core::level::link::link(level, page) {
            Ok(link) => {
                self.message = Some(match files::copy_text(&link) {
                    Ok(()) => format!(
                        "The link is copied ({} characters): whoever opens it plays the level \
                         on the page.",
                        link.len()
                    ),
                    Err(e) => format!("{e}: copy the link below by hand."),
                });
                self.link = Some(link);
            }
            Err(e) => {
                self.message = Some(e);
                self.link = None;
            }
        }
        Some(())
    }
}

/// Writes the draft to its file (a download on the page), checked first as `voxcast levels
/// check` would: a level with errors is not written. The saved level joins the list.
fn save(draft: &mut Draft, mut level: Level, lessons: &mut Lessons) -> String {
    let path = std::path::PathBuf::from(draft.file.trim());
    if let Err(e) = files::file_name(&path) {
        return e;
    }
    let path = path.with_extension("json");
    // On the desktop the level now lives in that file: a data set beside it is named as such,
    // so the folder moves as a whole. On the page the file is a download, and the level stays
    // where it was read from (its data sets are still found beside that).
    let on_disk = cfg!(not(target_arch = "wasm32"));
    if on_disk {
        relative_to(&mut level, &path);
        level.origin = Origin::File(path.clone());
    }
    let text = voxcast_core::level::to_text(&level);
    let checked = voxcast_core::level::check::read(
        &text,
        level.origin.clone(),
        &voxcast_core::level::check::OnDisk,
    );
    if checked.has_errors() {
        let first = checked
            .problems
            .first()
            .map(|p| p.to_string())
            .unwrap_or_default();
        return format!("Not saved: {first}");
    }
    match files::save(&path, text.as_bytes(), "application/json") {
        Ok(done) => {
            draft.level = Some(level.clone());
            draft.file = path.display().to_string();
            lessons.keep_level(level);
            let warnings = checked.problems.len();
            if warnings == 0 {
                done
            } else {
                format!(
                    "{done} ({warnings} warning{}: voxcast levels check says which)",
                    if warnings == 1 { "" } else { "s" }
                )
            }
        }
        Err(e) => format!("Not saved: {e}"),
    }
}

/// Names each data set of `level` that lies in `path`'s folder (or below it) relative to it.
fn relative_to(level: &mut Level, path: &std::path::Path) {
    let Some(dir) = path.parent().and_then(|d| std::path::absolute(d).ok()) else {
        return;
    };
    let relative = |name: &mut String| {
        let p = std::path::Path::new(name.as_str());
        if let Some(rest) = std::path::absolute(p)
            .ok()
            .filter(|_| !name.starts_with("builtin:") && !name.starts_with("density:"))
            .and_then(|abs| abs.strip_prefix(&dir).ok().map(|r| r.to_path_buf()))
        {
            *name = rest.display().to_string();
        }
    };
    relative(&mut level.scene.volume);
    for step in &mut level.steps {
        if let Some(v) = step.scene.as_mut().and_then(|s| s.volume.as_mut()) {
            relative(v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A level saved beside its data sets names them relative to itself (so the folder can be
    /// copied, or hosted beside the page, whole); one elsewhere keeps its full path, and a
    /// built-in its name.
    #[test]
    fn data_sets_beside_the_level_are_named_relative_to_it() {
        let course = std::env::temp_dir().join(format!("voxcast-course-{}", std::process::id()));
        let mut level = Level::all().remove(0);
        level.scene.volume = course.join("ct_head.nrrd").display().to_string();
        let elsewhere = std::env::temp_dir().join("elsewhere/mri.nii.gz");
        let beneath = course.join("data/brain.nrrd");
        level.steps[0].scene = Some(voxcast_core::level::StepScene {
            volume: Some(beneath.display().to_string()),
            ..Default::default()
        });
        level.steps[1].scene = Some(voxcast_core::level::StepScene {
            volume: Some(elsewhere.display().to_string()),
            ..Default::default()
        });
        level.steps[2].scene = Some(voxcast_core::level::StepScene {
            volume: Some("builtin:bucky".into()),
            ..Default::default()
        });
        relative_to(&mut level, &course.join("my_level.json"));
        let volume = |k: usize| level.steps[k].scene.as_ref().unwrap().volume.clone();
        assert_eq!(level.scene.volume, "ct_head.nrrd");
        assert_eq!(volume(0).as_deref(), Some("data/brain.nrrd"));
        assert_eq!(volume(1), Some(elsewhere.display().to_string()));
        assert_eq!(volume(2).as_deref(), Some("builtin:bucky"));
        // Read back from where it was saved, each name is found where it was.
        let read = Level {
            origin: Origin::File(course.join("my_level.json")),
            ..level
        };
        assert_eq!(
            read.resolve("ct_head.nrrd"),
            course.join("ct_head.nrrd").display().to_string()
        );
    }
}
