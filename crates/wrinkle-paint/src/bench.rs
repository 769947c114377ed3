//! The paint page's speed, measured in-process on the session (no browser, no network): a frame while
//! orbiting (camera move, render, JPEG) and a brush dab's latency (dab, texture update, render, JPEG).

use crate::brush::Brush;
use crate::frames::{encode_frame, FrameFormat};
use crate::session::{Orbit, Session};
use std::time::Instant;
use wrinkle::Result;

/// Milliseconds per step of each workload, in the order measured.
pub struct PaintTimes {
    pub orbit: Vec<f64>,
    /// Dabs on the colour channel (its texture rebuilt) and on the height (the bump table rebuilt).
    pub colour_dab: Vec<f64>,
    pub height_dab: Vec<f64>,
}

/// `steps` orbit frames (3 degrees apart) and `steps` dabs of radius `radius` pixels, 8 pixels apart across
/// the view's middle row, each ending with its frame encoded as JPEG (what the page receives).
pub fn measure(session: &mut Session, steps: usize, radius: f32) -> Result<PaintTimes> {
    let start = session.state().camera;
    let mut orbit = Vec::with_capacity(steps);
    for k in 0..=steps {
        let t = Instant::now();
        session.set_camera(Orbit { yaw: start.yaw + 3.0 * k as f32, ..start })?;
        encode_frame(session.frame()?, FrameFormat::Jpeg)?;
        // The first frame warms the caches and the thread pool.
        if k > 0 {
            orbit.push(t.elapsed().as_secs_f64() * 1e3);
        }
    }
    session.set_camera(start)?;
    session.frame()?;
    let colour = serde_json::json!({"radius": radius, "color": [0.9, 0.2, 0.1]});
    let height = serde_json::json!({"radius": radius, "channel": "height", "value": 1.0});
    let colour_dab = dabs(session, steps, colour)?;
    let height_dab = dabs(session, steps, height)?;
    Ok(PaintTimes { orbit, colour_dab, height_dab })
}

/// One stroke of `steps` dabs 8 pixels apart across the view's middle row, undone afterwards.
fn dabs(session: &mut Session, steps: usize, brush: serde_json::Value) -> Result<Vec<f64>> {
    let (w, h) = (session.state().width as f32, session.state().height as f32);
    let brush: Brush = serde_json::from_value(brush).expect("the bench's brushes are valid");
    session.begin_stroke(brush)?;
    let mut times = Vec::with_capacity(steps);
    for k in 0..steps {
        let x = w * 0.5 + 8.0 * (k as f32 - steps as f32 * 0.5);
        let t = Instant::now();
        session.stroke_to(x, h * 0.5)?;
        encode_frame(session.frame()?, FrameFormat::Jpeg)?;
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    session.end_stroke();
    session.undo(false);
    Ok(times)
}
