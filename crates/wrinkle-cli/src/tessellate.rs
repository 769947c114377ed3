//! `wrinkle tessellate`: a scene's geometry written as an OBJ model (parametric surfaces as triangle
//! grids with their exact normals and (u,v), meshes as read, all in world space).

use crate::render::load_scene;
use clap::Args;
use std::path::PathBuf;
use wrinkle::image::output::write_atomic;
use wrinkle::{Error, Result};

#[derive(Args, Debug)]
#[command(
    after_help = "Examples:\n  wrinkle tessellate scenes/teapot.toml -o teapot.obj               Newell's 32 patches as 12 x 12 quads each\n  wrinkle tessellate scenes/teapot.toml -o teapot.obj --segments 32  finer\n\nPositions equal bit for bit are shared, so patches that meet stay watertight; materials stay in the scene."
)]
pub struct TessellateArgs {
    /// Scene file (TOML); the embedded cover scene when omitted.
    pub scene: Option<PathBuf>,
    /// The model (OBJ).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Quads along u and along v of each parametric surface.
    #[arg(long, default_value_t = 12)]
    pub segments: usize,
}

pub fn run(args: &TessellateArgs) -> Result<()> {
    crate::output::require_extension(&args.output, &["obj"])?;
    let scene = load_scene(args.scene.as_deref())?;
    let text = scene.to_obj(args.segments)?;
    write_atomic(&args.output, |w| w.write_all(text.as_bytes()).map_err(|e| Error::write(&args.output, e)))
}
