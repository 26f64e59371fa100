//! How the window is shared between the scene and the panels. The scene keeps at least half the
//! window's width and most of its height at any size from 800×500 up (a school laptop's browser
//! tab): a narrow strip on the left holds a button for each side panel (the settings, the
//! rays), which show or hide it; where both would leave the scene less than half the width
//! ([`Shares::both_fit`]) only one is open at a time. The side panels are as wide as their share
//! allows, the breakdown as tall as its share, and a level's text folds to its first line
//! where the window is low (see `levels_window`).

use bevy::prelude::*;
use bevy_egui::egui;
use voxcast_core::level::Control;

/// The share of the window's width the scene keeps whatever is open.
pub const SCENE_WIDTH: f32 = 0.5;
/// The share of the window's height the breakdown may take at most.
pub const BREAKDOWN_HEIGHT: f32 = 0.25;
/// The strip of panel buttons on the left, points wide.
pub const STRIP: f32 = 34.0;
/// The widths the side panels ask for, points (as wide as that where there is room).
pub const SETTINGS_WIDTH: f32 = 356.0;
pub const RAYS_WIDTH: f32 = 240.0;
/// Below this width a side panel's controls no longer fit: the scene gives up its share
/// before a panel goes narrower.
pub const SIDE_MIN: f32 = 220.0;
/// Windows lower than this fold a level's text to its first line at first.
pub const LOW: f32 = 700.0;

/// A side panel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Settings,
    Rays,
}

/// Which side panels the student has open, whether a level's text is unfolded, and this
/// frame's shares of the window.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct Layout {
    pub settings: bool,
    pub rays: bool,
    /// The level's text shown whole (`None`: as the window's height has it).
    pub level_text: Option<bool>,
    pub shares: Shares,
}

impl Default for Layout {
    fn default() -> Self {
        Self {
            settings: true,
            rays: true,
            level_text: None,
            shares: Shares::of(Vec2::new(1280.0, 720.0), 2),
        }
    }
}

/// The sizes panels may take in a window of `size` points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shares {
    /// Both side panels at the widths they ask for leave the scene its share.
    pub both_fit: bool,
    /// The width the side panels may take together.
    sides: f32,
    /// Both side panels are open.
    both_open: bool,
    pub breakdown_max: f32,
    /// A level's text starts folded.
    pub fold_level_text: bool,
}

impl Shares {
    /// The shares of a window of `size` points with `open` side panels.
    pub fn of(size: Vec2, open: usize) -> Self {
        let sides = (size.x * (1.0 - SCENE_WIDTH) - STRIP).max(0.0);
        Self {
            both_fit: SETTINGS_WIDTH + RAYS_WIDTH <= sides,
            sides,
            both_open: open >= 2,
            breakdown_max: size.y * BREAKDOWN_HEIGHT,
            fold_level_text: size.y < LOW,
        }
    }

    /// The most `side` may take: all the sides' width when it is open alone, else its part
    /// of it in proportion to the widths the two ask for (never below [`SIDE_MIN`]).
    pub fn side_max(&self, side: Side) -> f32 {
        let want = match side {
            Side::Settings => SETTINGS_WIDTH,
            Side::Rays => RAYS_WIDTH,
        };
        let share = if self.both_open {
            self.sides * want / (SETTINGS_WIDTH + RAYS_WIDTH)
        } else {
            self.sides
        };
        share.max(SIDE_MIN)
    }

    /// The width `side` opens at.
    pub fn side_width(&self, side: Side) -> f32 {
        let want = match side {
            Side::Settings => SETTINGS_WIDTH,
            Side::Rays => RAYS_WIDTH,
        };
        want.min(self.side_max(side))
    }
}

/// What changed since the last frame that brings the layout within its shares again.
pub(super) struct Rearrange {
    /// A new mode: both panels shown again, as far as they fit.
    pub new_mode: bool,
    /// The control a level's step frames, if any: its panel is shown.
    pub spot: Option<Control>,
}

impl Layout {
    /// Whether `side` is shown.
    pub fn open(&self, side: Side) -> bool {
        match side {
            Side::Settings => self.settings,
            Side::Rays => self.rays,
        }
    }

    /// Shows or hides `side`; where both do not fit, showing one hides the other.
    pub fn set(&mut self, side: Side, open: bool, shares: &Shares) {
        match side {
            Side::Settings => self.settings = open,
            Side::Rays => self.rays = open,
        }
        if open && !shares.both_fit {
            match side {
                Side::Settings => self.rays = false,
                Side::Rays => self.settings = false,
            }
        }
    }

    /// Brings the layout within `shares`: one side panel where both do not fit (the
    /// settings, unless only the rays were shown).
    pub fn fit(&mut self, shares: &Shares) {
        if !shares.both_fit && self.settings && self.rays {
            self.rays = false;
        }
    }

    /// Shows the panel holding `control` (framed by a level's step), so it is in view.
    pub fn reveal(&mut self, control: Control, shares: &Shares) {
        let side = match control {
            Control::PixelGrid => Some(Side::Rays),
            Control::Breakdown => None,
            _ => Some(Side::Settings),
        };
        if let Some(side) = side
            && !self.open(side)
        {
            self.set(side, true, shares);
        }
    }

    /// This frame's shares of a window of `size` points, after the panels are brought within
    /// them (`rearrange`: on a new size, step or mode). The shares are taken from the panels
    /// left open: taken before, a window too narrow for both gave the settings panel a half
    /// share as if the rays panel stood beside it, and egui kept that first width.
    pub(super) fn arrange(&mut self, size: Vec2, rays_shown: bool, rearrange: Option<Rearrange>) {
        let open = |l: &Self| usize::from(l.settings) + usize::from(l.rays && rays_shown);
        if let Some(r) = rearrange {
            if r.new_mode {
                self.settings = true;
                self.rays = true;
            }
            let shares = Shares::of(size, open(self));
            self.fit(&shares);
            if let Some(spot) = r.spot {
                self.reveal(spot, &shares);
            }
        }
        self.shares = Shares::of(size, open(self));
    }
}

/// The window's shares this frame, the layout brought within them (and the panel holding a
/// framed control shown), and the strip of panel buttons docked on the left.
pub(super) fn layout_strip(
    mut contexts: bevy_egui::EguiContexts,
    mut layout: ResMut<Layout>,
    mut dock: ResMut<super::Dock>,
    lessons: Res<crate::sandbox::levels::Lessons>,
    cameras: Query<&crate::sandbox::inspect::virtual_camera::VirtualCamera>,
    mode: Res<State<crate::sandbox::shared::mode::Mode>>,
    mut last: Local<
        Option<(
            egui::Vec2,
            Option<Control>,
            crate::sandbox::shared::mode::Mode,
        )>,
    >,
) -> Result {
    let ctx = contexts.ctx_mut()?.clone();
    let size = ctx.content_rect().size();
    let rays_shown = cameras.single().is_ok_and(|c| c.shown);
    let mut next = layout.clone();
    // On a new size, a new framed control or a new mode (not every frame: the student may
    // close a panel); a new mode starts from both panels shown, as far as they fit.
    let now = (size, lessons.spot, *mode.get());
    let rearrange = (*last != Some(now)).then(|| Rearrange {
        new_mode: last.is_none_or(|(_, _, m)| m != now.2),
        spot: lessons.spot,
    });
    *last = Some(now);
    next.arrange(Vec2::new(size.x, size.y), rays_shown, rearrange);
    dock.show(&ctx, "strip", |dock_ui| {
        egui::Panel::left("strip")
            .resizable(false)
            .exact_size(STRIP)
            .show(dock_ui, |ui| {
                let shares = next.shares;
                strip(ui, &mut next, &shares, rays_shown)
            });
    });
    if next != *layout {
        *layout = next;
    }
    Ok(())
}

/// The strip's buttons.
fn strip(ui: &mut egui::Ui, layout: &mut Layout, shares: &Shares, rays_shown: bool) {
    let buttons = [
        (
            Side::Settings,
            "≡",
            "Settings: the volume, ray casting, shading, transfer function, preview",
        ),
        (
            Side::Rays,
            "⇶",
            "Rays: the virtual camera's rays, their image, and a ray's breakdown",
        ),
    ];
    ui.vertical_centered(|ui| {
        for (side, glyph, tip) in buttons {
            if side == Side::Rays && !rays_shown {
                continue;
            }
            let open = layout.open(side);
            let name = match side {
                Side::Settings => "settings panel",
                Side::Rays => "rays panel",
            };
            let button = egui::Button::new(egui::RichText::new(glyph).size(18.0)).selected(open);
            let response = super::target(ui.add_sized([STRIP - 6.0, STRIP - 6.0], button), name);
            if response
                .on_hover_text(format!("{tip} ({} it)", if open { "hide" } else { "show" }))
                .clicked()
            {
                layout.set(side, !open, shares);
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At every window from 800×500 up, whatever is open, the side panels leave the scene at
    /// least half the width, and the breakdown with a folded level text most of the height.
    #[test]
    fn the_scene_keeps_its_share_at_every_size() {
        for w in (800..=2560).step_by(40) {
            for h in (500..=1440).step_by(20) {
                let size = Vec2::new(w as f32, h as f32);
                for (settings, rays) in [(true, true), (true, false), (false, true), (false, false)]
                {
                    let mut layout = Layout {
                        settings,
                        rays,
                        ..default()
                    };
                    let open = usize::from(settings) + usize::from(rays);
                    layout.fit(&Shares::of(size, open));
                    let open = usize::from(layout.settings) + usize::from(layout.rays);
                    let shares = Shares::of(size, open);
                    // The panels as wide as the student may drag them.
                    let sides = [(layout.settings, Side::Settings), (layout.rays, Side::Rays)]
                        .iter()
                        .filter(|(o, _)| *o)
                        .map(|(_, side)| shares.side_max(*side))
                        .sum::<f32>();
                    let scene = w as f32 - STRIP - sides;
                    assert!(scene >= 0.5 * w as f32, "{w}×{h} {layout:?}: scene {scene}");
                    assert!(shares.breakdown_max <= 0.25 * h as f32);
                    assert_eq!(shares.fold_level_text, h < 700);
                }
            }
        }
    }

    /// A window too narrow for both side panels opens the settings alone at the width it
    /// asks for (it opened at `SIDE_MIN`, a share as if the rays panel were beside it).
    #[test]
    fn a_narrow_window_opens_the_settings_at_their_width() {
        for (w, h) in [(800.0, 500.0), (1024.0, 576.0), (1100.0, 700.0)] {
            let mut layout = Layout::default();
            let first = Some(Rearrange {
                new_mode: true,
                spot: None,
            });
            layout.arrange(Vec2::new(w, h), true, first);
            assert!(layout.settings && !layout.rays, "{w}×{h}: {layout:?}");
            let width = layout.shares.side_width(Side::Settings);
            assert_eq!(width, SETTINGS_WIDTH.min(w * (1.0 - SCENE_WIDTH) - STRIP));
            assert!(width > SIDE_MIN, "{w}×{h}: {width}");
        }
        // Where both fit, each keeps the width it asks for.
        let mut layout = Layout::default();
        let first = Some(Rearrange {
            new_mode: true,
            spot: None,
        });
        layout.arrange(Vec2::new(1920.0, 1080.0), true, first);
        assert!(layout.settings && layout.rays);
        assert_eq!(layout.shares.side_width(Side::Settings), SETTINGS_WIDTH);
        assert_eq!(layout.shares.side_width(Side::Rays), RAYS_WIDTH);
    }

    #[test]
    fn where_both_do_not_fit_showing_one_hides_the_other() {
        let narrow = Shares::of(Vec2::new(1024.0, 576.0), 1);
        let wide = Shares::of(Vec2::new(1920.0, 1080.0), 2);
        assert!(!narrow.both_fit && wide.both_fit);
        let mut layout = Layout::default();
        layout.fit(&narrow);
        assert!(layout.settings && !layout.rays, "the settings stay");
        layout.set(Side::Rays, true, &narrow);
        assert!(layout.rays && !layout.settings);
        layout.reveal(Control::Step, &narrow);
        assert!(
            layout.settings && !layout.rays,
            "a step's control comes into view"
        );
        layout.set(Side::Rays, true, &wide);
        assert!(layout.rays && layout.settings);
    }
}
