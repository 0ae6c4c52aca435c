//! Pictures of the robot itself: a stick figure (bodies, joints, feet) in three views, as a
//! still of a plan's postures (`robot.png`) or an animation (`step.gif`, or the physics robot's
//! walk). One drawing serves every picture: build [`StickFigure`]s from body poses, then
//! [`write_gif`] or [`draw_views`].

mod animation;
mod blocks;
mod figure;
mod plan_views;
mod rgb;
mod view;
mod views;
mod walk;

pub use animation::{FRAME_SIZE, Frame, write_gif, write_gif_following};
pub use figure::{Bone, FigureError, FootMark, Part, StickFigure};
pub use plan_views::{MAX_FRAMES, PHASES, animate_step, plan_ground, plot_robot};
pub use rgb::{camera_half_extent, pose_rgb, scene_ground};
pub use view::View;
pub use views::{Bounds, Ground, ViewLayout, draw_legend, draw_views};
pub use walk::{WalkGif, WalkPose, animate_walk, animate_walk_on, walk_figure};
