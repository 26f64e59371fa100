//! Every check tests what its step asks: each level played step by step on the core's
//! `Situation`, as the sandbox gathers it. At every step a wrong action — the click a careless
//! student makes, half of what the words ask, or the right control moved the wrong way — is
//! refused, and the action the words name is accepted; the state it leaves opens the next
//! step, as in the sandbox, where no objective may be met before the player acts.

use voxcast_core::classify::Region;
use voxcast_core::clip::ClipPlane;
use voxcast_core::composite::Method;
use voxcast_core::glam::Vec3;
use voxcast_core::level::{Level, Objective, RayDensityFacts, Situation};
use voxcast_core::transfer::TransferFunction;

/// A change the player makes to what the objectives see.
type Act<'a> = &'a dyn Fn(&mut Situation);

/// A level played step by step from the situation its scene opens with.
struct Play {
    level: Level,
    step: usize,
    state: Situation,
}

impl Play {
    /// Level `id`, its scene set up as `open` describes.
    fn new(id: &str, open: impl FnOnce(&mut Situation)) -> Self {
        let level = Level::all().into_iter().find(|l| l.id == id).unwrap();
        let mut state = defaults();
        state.preview_on = level.scene.preview;
        state.virtual_pixels_across = level.scene.rays.unwrap_or(0);
        open(&mut state);
        Self {
            level,
            step: 0,
            state,
        }
    }

    fn objective(&self) -> &Objective {
        &self.level.steps[self.step].objective
    }

    /// A step only read: Next is open at once.
    fn read(&mut self) {
        assert_eq!(self.objective(), &Objective::Read, "{}", self.here());
        self.step += 1;
    }

    /// A step that asks for something: not met as it opens, nor after any of the `wrong`
    /// actions; met after `right`, whose state opens the next step.
    fn step(&mut self, wrong: &[(&str, Act)], right: Act) {
        let open = self.state.clone();
        let objective = self.objective().clone();
        let after = |act: Act| {
            let mut s = open.clone();
            act(&mut s);
            s.at_open = Some(Box::new(open.clone()));
            s
        };
        assert!(
            !objective.met(&after(&|_| {})),
            "{}: met as it opens ({objective:?})",
            self.here()
        );
        for (what, act) in wrong {
            assert!(
                !objective.met(&after(*act)),
                "{}: accepted a wrong action, {what} ({objective:?})",
                self.here()
            );
        }
        let done = after(right);
        assert!(
            objective.met(&done),
            "{}: the right action is refused ({objective:?})",
            self.here()
        );
        // A prediction belongs to its step: the next opens with nothing typed.
        self.state = Situation {
            at_open: None,
            prediction: None,
            ..done
        };
        self.step += 1;
    }

    fn here(&self) -> String {
        format!("{} step {}", self.level.id, self.step + 1)
    }
}

impl Drop for Play {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            assert_eq!(
                self.step,
                self.level.steps.len(),
                "{}: steps left unplayed",
                self.level.id
            );
        }
    }
}

/// What a level opens with: the settings' defaults, one white headlight.
fn defaults() -> Situation {
    Situation {
        method: Some(Method::Accumulate),
        step_voxels: 0.5,
        early_termination: true,
        opacity_correction: true,
        shading: true,
        classification: "table",
        light_kinds: vec!["headlight"],
        light_colors: vec![[1.0; 3]],
        light_distances: vec![None],
        specular: "blinn-phong",
        ka: 0.2,
        trilinear: true,
        supersampling: 1,
        skipping: true,
        preview_scale: 1.0,
        ..Situation::default()
    }
}

/// A click on the pixel whose ray is on show in the breakdown.
fn click(s: &mut Situation) {
    s.ray_selected = true;
    s.ray_clicks += 1;
}

fn transfer(preset: &str) -> TransferFunction {
    voxcast_core::preset::by_name(preset).unwrap().transfer
}

/// The transfer function with a point of `color` and opacity `alpha` at `value`.
fn with_point(s: &mut Situation, value: f32, color: [f32; 3], alpha: f32) {
    let t = s.transfer.take().unwrap();
    let (t, i) = t.with_point_added(value, alpha).unwrap();
    s.transfer = Some(t.with_point_color(i, color).unwrap());
}

#[test]
fn rays() {
    let mut p = Play::new("rays", |_| {});
    p.read();
    p.step(
        &[
            ("8 pixels down, 4 across", &|s| s.virtual_pixels_across = 4),
            ("7 across", &|s| s.virtual_pixels_across = 7),
        ],
        &|s| s.virtual_pixels_across = 8,
    );
    p.step(
        &[("a ray selected before, no click", &|s| {
            s.ray_selected = true
        })],
        &click,
    );
}

#[test]
fn sampling() {
    let mut p = Play::new("sampling", |s| {
        s.ray_values = vec![10.0, 90.0, 40.0];
    });
    p.read();
    p.step(
        &[("a ray selected before, no click", &|s| {
            s.ray_selected = true
        })],
        &click,
    );
    // The selected ray takes 25 samples at the step of 0.3, is 7.2 long and crosses 12 cells.
    p.step(
        &[
            ("one too few: the first sample forgotten", &|s| {
                s.prediction = Some((24.0, 25.0))
            }),
            ("the length over the step, not a count", &|s| {
                s.prediction = Some((24.6, 25.0))
            }),
        ],
        // (The step's scene set the step to 0.3; the step that asks for 0.25 sets it back
        // to 0.5 as it opens.)
        &|s| s.prediction = Some((25.0, 25.0)),
    );
    p.step(
        &[
            ("divided by 15, the samples' gaps of 16 samples", &|s| {
                s.prediction = Some((0.48, 0.45))
            }),
            ("the fixed step's own 0.3", &|s| {
                s.prediction = Some((0.3, 0.45))
            }),
        ],
        &|s| s.prediction = Some((0.455, 0.45)),
    );
    p.step(
        &[
            ("the planes passed, not the cells", &|s| {
                s.prediction = Some((11.0, 12.0))
            }),
            ("the samples counted instead", &|s| {
                s.prediction = Some((25.0, 12.0))
            }),
        ],
        &|s| s.prediction = Some((12.0, 12.0)),
    );
    p.step(
        &[
            ("0.3 voxel, as the steps before had it", &|s| {
                s.step_voxels = 0.3
            }),
            ("a coarser step", &|s| s.step_voxels = 2.0),
        ],
        &|s| s.step_voxels = 0.25,
    );
    p.step(
        &[("the knob of another trade measured", &|s| {
            s.measured_knob = Some("opacity-cutoff")
        })],
        &|s| {
            s.trade_measured = true;
            s.measured_knob = Some("step");
        },
    );
    p.step(
        &[
            ("a ray clicked, nothing opened", &click),
            ("a sample that is not the highest", &|s| {
                s.opened_sample = Some(2)
            }),
        ],
        &|s| s.opened_sample = Some(1),
    );
}

#[test]
fn jitter() {
    let mut p = Play::new("jitter", |_| {});
    p.read();
    p.step(&[("1.5 voxels", &|s| s.step_voxels = 1.5)], &|s| {
        s.step_voxels = 2.0
    });
    p.step(
        &[("supersampling instead", &|s| s.supersampling = 2)],
        &|s| s.jitter = true,
    );
    p.step(
        &[
            ("jitter off again", &|s| {
                s.jitter = false;
                s.supersampling = 2;
            }),
            ("no supersampling", &|s| s.step_voxels = 1.0),
        ],
        &|s| s.supersampling = 2,
    );
    p.step(&[("0.75 voxel", &|s| s.step_voxels = 0.75)], &|s| {
        s.step_voxels = 0.5
    });
}

#[test]
fn trilinear() {
    // P2's value by the lecture's formula, and the worked composite's red (the level's ramp).
    let (p2, p1, p3, red) = (4.9875, 4.9768, 5.0712, 0.5404);
    let mut p = Play::new("trilinear", |s| {
        s.virtual_pixels_across = 1;
        s.opacity_correction = false;
        s.shading = false;
    });
    p.read();
    for truth in [p2, p1, p3, red] {
        p.step(
            &[
                ("an answer 0.02 off", &|s| {
                    s.prediction = Some((truth + 0.02, truth))
                }),
                ("the value at another point", &|s| {
                    s.prediction = Some((5.0, truth))
                }),
            ],
            &|s| s.prediction = Some((truth + 0.004, truth)),
        );
        p.state.prediction = None;
    }
    p.step(
        &[
            ("back to front, the pixel not clicked", &|s| {
                s.back_to_front = true;
                s.ray_selected = true;
            }),
            ("the pixel clicked, front to back", &click),
        ],
        &|s| {
            s.back_to_front = true;
            click(s);
        },
    );
}

#[test]
fn nearest() {
    let mut p = Play::new("nearest", |_| {});
    p.read();
    p.step(
        &[("measured with nearest", &|s| {
            s.trilinear = false;
            s.trade_measured = true;
            s.measured_knob = Some("step");
        })],
        &|s| {
            s.trade_measured = true;
            s.measured_knob = Some("step");
        },
    );
    // A change of settings leaves the last measurement behind.
    p.state.trade_measured = false;
    p.state.measured_knob = None;
    p.step(&[("still trilinear", &|_| {})], &|s| s.trilinear = false);
    p.step(
        &[("measured with trilinear again", &|s| {
            s.trilinear = true;
            s.trade_measured = true;
            s.measured_knob = Some("step");
        })],
        &|s| {
            s.trade_measured = true;
            s.measured_knob = Some("step");
        },
    );
}

#[test]
fn methods() {
    let mut p = Play::new("methods", |_| {});
    p.read();
    for (wrong, right) in [
        (Method::First, Method::Maximum),
        (Method::Maximum, Method::Minimum),
        (Method::Sum, Method::Average),
    ] {
        p.step(&[("another method", &|s| s.method = Some(wrong))], &|s| {
            s.method = Some(right)
        });
    }
}

#[test]
fn opacity() {
    let mut p = Play::new("opacity", |_| {});
    p.read();
    p.step(
        &[
            ("correction off, the step slider left alone", &|s| {
                s.opacity_correction = false
            }),
            ("the step moved, correction on", &|s| s.step_voxels = 1.0),
        ],
        &|s| {
            s.opacity_correction = false;
            s.step_voxels = 1.0;
        },
    );
    p.step(
        &[("opacity correction back on", &|s| {
            s.opacity_correction = true
        })],
        &|s| s.early_termination = false,
    );
    p.step(
        &[("early termination on again", &|s| {
            s.early_termination = true
        })],
        &|s| s.back_to_front = true,
    );
}

#[test]
fn first_hit() {
    let mut p = Play::new("first-hit", |s| s.target = Some(40.0));
    p.step(
        &[("Maximum", &|s| s.method = Some(Method::Maximum))],
        &|s| s.method = Some(Method::First),
    );
    p.step(
        &[
            ("the target at the scalp", &|s| s.target = Some(90.0)),
            ("the target at the bone", &|s| s.target = Some(220.0)),
            ("the skull's target under another method", &|s| {
                s.target = Some(150.0);
                s.method = Some(Method::Maximum);
            }),
        ],
        &|s| s.target = Some(150.0),
    );
    p.step(
        &[("the samples' cost instead", &|s| {
            s.preview_cost_view = Some("samples")
        })],
        &|s| s.preview_cost_view = Some("depth"),
    );
    p.step(&[("the box's scale kept", &|_| {})], &|s| {
        s.preview_cost_view = Some("depth-of-hits")
    });
    p.step(
        &[
            ("shading off under the depth view", &|s| s.shading = false),
            ("the picture again, shading on", &|s| {
                s.preview_cost_view = None
            }),
        ],
        &|s| {
            s.preview_cost_view = None;
            s.shading = false;
        },
    );
    p.step(&[("still off", &|_| {})], &|s| s.shading = true);
}

#[test]
fn levoy() {
    let mut p = Play::new("levoy", |_| {});
    p.step(
        &[("boundaries first", &|s| s.classification = "boundaries")],
        &|s| s.classification = "iso-contours",
    );
    p.step(
        &[("value and gradient", &|s| {
            s.classification = "value-gradient"
        })],
        &|s| s.classification = "boundaries",
    );
}

#[test]
fn value_gradient() {
    let mut p = Play::new("value-gradient", |_| {});
    p.read();
    p.step(
        &[("iso-contours", &|s| s.classification = "iso-contours")],
        &|s| s.classification = "value-gradient",
    );
    let region = |value: [f32; 2], gradient: [f32; 2], opacity: f32| Region {
        value,
        gradient,
        opacity,
    };
    p.step(
        &[
            ("around the shell's gradients", &|s| {
                s.regions = vec![region([100.0, 120.0], [40.0, 60.0], 0.6)]
            }),
            ("up to a gradient of 60", &|s| {
                s.regions = vec![region([100.0, 120.0], [0.0, 60.0], 0.6)]
            }),
            ("around value 80", &|s| {
                s.regions = vec![region([70.0, 90.0], [0.0, 30.0], 0.6)]
            }),
            ("no opacity", &|s| {
                s.regions = vec![region([100.0, 120.0], [0.0, 30.0], 0.0)]
            }),
        ],
        &|s| s.regions = vec![region([100.0, 120.0], [0.0, 30.0], 0.6)],
    );
}

/// The bunny's box: 127 world units across each way; the point light starts a little outside
/// it, 0.6 of the diagonal from the centre.
#[test]
fn light() {
    let mut p = Play::new("light", |_| {});
    p.step(
        &[("a directional light", &|s| {
            s.light_kinds = vec!["directional"]
        })],
        &|s| {
            s.light_kinds = vec!["point"];
            s.light_distances = vec![Some(0.6)];
        },
    );
    p.step(
        &[
            ("kl raised, the light left where it was", &|s| {
                s.attenuated = true
            }),
            ("kl raised, the light moved nearer", &|s| {
                s.attenuated = true;
                s.light_distances = vec![Some(0.3)];
            }),
            ("moved away without a falloff", &|s| {
                s.light_distances = vec![Some(0.9)]
            }),
            ("kl raised, nudged a hair away", &|s| {
                s.attenuated = true;
                s.light_distances = vec![Some(0.62)];
            }),
        ],
        &|s| {
            s.attenuated = true;
            s.light_distances = vec![Some(0.9)];
        },
    );
}

#[test]
fn lights() {
    let mut p = Play::new("lights", |_| {});
    p.read();
    p.step(&[("the headlight alone", &|_| {})], &|s| {
        s.light_kinds.push("directional");
        s.light_colors.push([1.0; 3]);
        s.light_distances.push(None);
    });
    p.step(
        &[
            ("two warm lights", &|s| {
                s.light_colors = vec![[1.0, 0.5, 0.3], [1.0, 0.8, 0.2]]
            }),
            ("a cool and a green light", &|s| {
                s.light_colors = vec![[0.3, 0.5, 1.0], [0.3, 1.0, 0.3]]
            }),
        ],
        &|s| s.light_colors = vec![[1.0, 0.45, 0.3], [0.3, 0.55, 1.0]],
    );
    p.step(
        &[
            ("a sample one light reaches", &|s| {
                click(s);
                s.opened_sample = Some(3);
                s.opened_sample_lights = Some(1);
            }),
            ("an unshaded sample", &|s| {
                click(s);
                s.opened_sample = Some(0);
                s.opened_sample_lights = None;
            }),
        ],
        &|s| {
            click(s);
            s.opened_sample = Some(4);
            s.opened_sample_lights = Some(2);
        },
    );
    let spot = |s: &mut Situation| {
        s.light_kinds[1] = "spot";
        s.spot_ambient = true;
        s.light_distances[1] = Some(0.8);
    };
    p.step(
        &[
            ("emission and a spot, N·H kept", &|s| {
                s.emission = 0.15;
                spot(s);
            }),
            ("R·V, no emission", &|s| {
                spot(s);
                s.specular = "phong";
            }),
            ("R·V and emission, no light's ambient", &|s| {
                s.emission = 0.15;
                s.specular = "phong";
                s.light_kinds[1] = "spot";
            }),
            ("everything, but ka at 0", &|s| {
                s.emission = 0.15;
                spot(s);
                s.specular = "phong";
                s.ka = 0.0;
            }),
        ],
        &|s| {
            s.emission = 0.15;
            spot(s);
            s.specular = "phong";
        },
    );
    p.step(&[("white kept", &|_| {})], &|s| s.levoy_highlight = true);
    p.step(
        &[("Levoy's highlight off again", &|s| {
            s.levoy_highlight = false
        })],
        &|s| s.depth_cue = true,
    );
}

#[test]
fn transfer_function() {
    let mut p = Play::new("transfer", |s| s.transfer = Some(transfer("brainsmall")));
    p.read();
    p.step(
        &[
            ("0.05 at 40", &|s| with_point(s, 40.0, [0.5; 3], 0.05)),
            ("0 at 60 instead", &|s| with_point(s, 60.0, [0.5; 3], 0.0)),
        ],
        &|s| with_point(s, 40.0, [0.5; 3], 0.0),
    );
    const RED: [f32; 3] = [1.0, 0.0, 0.0];
    const GREEN: [f32; 3] = [0.0, 1.0, 0.0];
    const BLUE: [f32; 3] = [0.0, 0.0, 1.0];
    p.step(
        &[
            ("red at 180, where there are 4 voxels", &|s| {
                with_point(s, 180.0, RED, 0.8)
            }),
            ("red at 140, too faint", &|s| with_point(s, 140.0, RED, 0.3)),
            ("orange at 140", &|s| {
                with_point(s, 140.0, [1.0, 0.6, 0.0], 0.8)
            }),
        ],
        &|s| with_point(s, 140.0, RED, 0.8),
    );
    p.step(
        &[("green at 100", &|s| with_point(s, 100.0, GREEN, 0.5))],
        &|s| with_point(s, 120.0, GREEN, 0.5),
    );
    p.step(
        &[
            ("blue at 70 over the red's point, moved to 140", &|s| {
                with_point(s, 70.0, BLUE, 0.2);
                with_point(s, 140.0, BLUE, 0.2);
            }),
            ("blue at 70, too faint", &|s| {
                with_point(s, 70.0, BLUE, 0.05)
            }),
        ],
        &|s| with_point(s, 70.0, BLUE, 0.2),
    );
}

#[test]
fn clipping() {
    let mut p = Play::new("clipping", |_| {});
    p.read();
    let plane = |position: f32| {
        Some(ClipPlane {
            normal: Vec3::Z,
            position,
        })
    };
    p.step(
        &[("the crop box instead", &|s| s.clip.crop_hi.x = 0.5)],
        &|s| s.clip.plane = plane(0.0),
    );
    p.step(
        &[
            ("moved the other way", &|s| s.clip.plane = plane(0.4)),
            ("not deep enough", &|s| s.clip.plane = plane(-0.1)),
        ],
        &|s| s.clip.plane = plane(-0.4),
    );
    p.step(
        &[
            ("a click on a ray the cut leaves whole", &click),
            ("a cut ray selected before the step", &|s| {
                s.ray_selected = true;
                s.ray_cut = true;
            }),
        ],
        &|s| {
            click(s);
            s.ray_cut = true;
        },
    );
    p.step(&[("cropped to 0.6", &|s| s.clip.crop_hi.y = 0.6)], &|s| {
        s.clip.crop_hi.y = 0.5
    });
}

#[test]
fn acceleration() {
    let mut p = Play::new("acceleration", |_| {});
    p.read();
    // Render image shows `view` of a render of the settings on screen.
    let shown = |view: &'static str| move |s: &mut Situation| s.cost_view = Some(view);
    p.step(&[("samples", &shown("samples"))], &shown("stops"));
    p.step(&[("skipped", &shown("skipped"))], &shown("samples"));
    // Every change of settings leaves the render behind: Render image is no longer current.
    p.state.cost_view = None;
    p.step(&[("skipping off instead", &|s| s.skipping = false)], &|s| {
        s.early_termination = false
    });
    p.step(&[("stops", &shown("stops"))], &shown("samples"));
    p.state.cost_view = None;
    p.step(
        &[("early termination on again", &|s| {
            s.early_termination = true
        })],
        &|s| s.skipping = false,
    );
    p.step(&[("samples", &shown("samples"))], &shown("skipped"));
    p.step(
        &[("the samples in the preview", &|s| {
            s.preview_cost_view = Some("samples")
        })],
        &|s| s.skip_blocks_shown = true,
    );
    p.step(
        &[("the blocks hidden", &|s| s.skip_blocks_shown = false)],
        &|s| s.skipping = true,
    );
    p.step(
        &[
            ("the preview as samples, early termination left off", &|s| {
                s.preview_cost_view = Some("samples")
            }),
            ("early termination on, the preview as stops", &|s| {
                s.early_termination = true;
                s.preview_cost_view = Some("stops");
            }),
        ],
        &|s| {
            s.preview_cost_view = Some("samples");
            s.early_termination = true;
        },
    );
}

#[test]
fn preview_render() {
    let mut p = Play::new("preview-render", |_| {});
    p.step(&[("3/255 apart", &|s| s.compared_max = Some(3.0))], &|s| {
        s.compared_max = Some(1.0)
    });
    p.step(
        &[("a point light outside", &|s| s.light_kinds = vec!["point"])],
        &|s| {
            s.light_kinds = vec!["point"];
            s.light_inside_volume = true;
        },
    );
}

#[test]
fn slow_hardware() {
    let mut p = Play::new("slow-hardware", |_| {});
    p.read();
    p.step(&[("0.6", &|s| s.preview_scale = 0.6)], &|s| {
        s.preview_scale = 0.5
    });
    for (wrong, right) in [
        ("step", "preview-scale"),
        ("preview-scale", "preview-step-multiplier"),
        ("preview-step-multiplier", "adaptive-quality"),
    ] {
        p.step(
            &[("another knob", &|s| s.measured_knob = Some(wrong))],
            &|s| s.measured_knob = Some(right),
        );
    }
    p.step(
        &[("the resolution lowered", &|s| s.preview_scale = 0.25)],
        &|s| s.preview_on = false,
    );
    p.step(
        &[
            ("resolution 1, the preview left off", &|s| {
                s.preview_scale = 1.0
            }),
            ("on, at 0.5", &|s| s.preview_on = true),
        ],
        &|s| {
            s.preview_on = true;
            s.preview_scale = 1.0;
        },
    );
}

#[test]
fn ray_density() {
    let mut p = Play::new("ray-density", |_| {});
    p.read();
    let density = |source: &str, side: u32| RayDensityFacts {
        source: source.into(),
        trace: None,
        side,
    };
    p.step(
        &[("the Cornell box's rays", &|s| {
            s.ray_density = Some(density("builtin:cornell", 0))
        })],
        &|s| s.ray_density = Some(density("camera", 8)),
    );
    p.step(
        &[("128 across", &|s| {
            s.ray_density = Some(density("camera", 128))
        })],
        &|s| s.ray_density = Some(density("camera", 256)),
    );
    p.step(
        &[("the vector field", &|s| {
            s.ray_views = vec!["volume", "field"]
        })],
        &|s| s.ray_views = vec!["volume", "mesh"],
    );
}

#[test]
fn which_effect() {
    let mut p = Play::new("which-effect", |s| {
        s.ray_density = Some(RayDensityFacts {
            source: "builtin:cornell".into(),
            trace: Some(4),
            side: 0,
        });
        s.ray_views = vec!["volume"];
    });
    p.read();
    p.step(&[("the ray mesh", &|s| s.ray_views.push("mesh"))], &|s| {
        s.ray_views.push("field")
    });
    // Named effects: reflection for shadow, and so on; trace 0 and 1 are both primary.
    let name = |trace: u32| move |s: &mut Situation| s.named_effect = Some(trace);
    let compute = |trace: u32| {
        move |s: &mut Situation| {
            s.ray_density = Some(RayDensityFacts {
                source: "builtin:cornell".into(),
                trace: Some(trace),
                side: 0,
            });
            s.named_effect = None;
        }
    };
    p.step(&[("reflection", &name(2))], &name(4));
    p.step(&[("trace 1", &compute(1))], &compute(0));
    p.step(&[("shadow", &name(4))], &name(0));
    p.step(&[("trace 0 again", &compute(0))], &compute(1));
    p.step(&[("ambient occlusion", &name(3))], &name(1));
    p.step(&[("trace 3", &compute(3))], &compute(2));
    p.step(&[("primary", &name(0))], &name(2));
    p.step(&[("trace 2 again", &compute(2))], &compute(3));
    p.step(&[("reflection", &name(2))], &name(3));
    // A study question is met only by the right answer to that question (the sandbox keeps
    // a wrong one as an answer, and meets nothing with it).
    for (trace, question) in [
        (1, "camera"),
        (0, "density-high"),
        (4, "hits"),
        (4, "density-low"),
    ] {
        p.step(
            &[
                ("the same question of another trace", &|s| {
                    s.studied = Some(((trace + 1) % 5, question.into()))
                }),
                ("another question", &|s| {
                    s.studied = Some((trace, "none".into()))
                }),
            ],
            &|s| s.studied = Some((trace, question.into())),
        );
        p.state.studied = None;
    }
}

#[test]
fn binary() {
    let step = |at: f32, width: f32, low: f32, high: f32| {
        move |s: &mut Situation| {
            let c = [0.9, 0.9, 0.8];
            s.transfer = Some(
                TransferFunction::new(
                    "binary",
                    vec![
                        voxcast_core::transfer::ControlPoint::new(0.0, c, low),
                        voxcast_core::transfer::ControlPoint::new(at - width / 2.0, c, low),
                        voxcast_core::transfer::ControlPoint::new(at + width / 2.0, c, high),
                        voxcast_core::transfer::ControlPoint::new(255.0, c, high),
                    ],
                )
                .unwrap(),
            )
        }
    };
    let mut p = Play::new("binary", |s| s.transfer = Some(transfer("head")));
    p.read();
    p.step(
        &[
            (
                "a step at 100: the brain stays",
                &step(100.0, 10.0, 0.0, 1.0),
            ),
            ("a ramp from 130 to 170", &step(150.0, 40.0, 0.0, 1.0)),
            ("half opaque above", &step(150.0, 4.0, 0.0, 0.5)),
            ("faint below", &step(150.0, 4.0, 0.05, 1.0)),
            ("the preset's opacities", &|s| {
                s.transfer = Some(transfer("head"))
            }),
        ],
        &step(150.0, 10.0, 0.0, 1.0),
    );
    p.read();
}
