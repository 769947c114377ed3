//! `wrinkle paint`: 3D painting on models in the browser (docs/paint.md). The course's three parts of a 3D
//! paint system: real-time rendering (wrinkle's own renderer, streamed to the page), the translation from
//! the mouse pixel to the texture (the item buffer and each texel's points on the surface) and a brush
//! depositing on the texture atlas.
//!
//! | module | job |
//! | --- | --- |
//! | `channels` | the atlas's colour, height, specular and opacity texels, stored as saved |
//! | `surface_points` | where on the model each texel lies, and a grid to find them by distance |
//! | `brush` | the brush, its falloff, a stroke's deposit and its undoable change |
//! | `model` | the scene or model painted, its painted material, the saved scene file |
//! | `session` | the camera, frames with their item buffer, strokes, undo, saving |
//! | `frames` | frames as JPEG or PNG |
//! | `server`, `page` | the HTTP API, the WebSocket and the embedded page |
//! | `bench` | frame and dab latency, measured in-process |

pub mod bench;
mod brush;
mod channels;
mod frames;
mod model;
mod page;
mod server;
mod session;
mod surface_points;

pub use brush::{Brush, RadiusSpace};
pub use channels::{Atlas, Channel};
pub use server::router;
pub use session::{Opening, Orbit, Saved, Session, State};

use std::net::{Ipv4Addr, SocketAddr};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use wrinkle::{Error, Result};

/// The port `wrinkle paint` tries first.
pub const DEFAULT_PORT: u16 = 8478;

/// What `wrinkle paint` was asked for.
pub struct Options {
    pub model: PathBuf,
    pub opening: Opening,
    /// A port that must be free; `None`: the first free one from `DEFAULT_PORT`.
    pub port: Option<u16>,
    pub save_dir: Option<PathBuf>,
}

/// Loads the model and serves the page and API on 127.0.0.1 until the process ends; `ready` is told the
/// address once the server listens.
pub fn serve(options: Options, ready: impl FnOnce(SocketAddr, &Session)) -> Result<()> {
    let mut session = Session::open(&options.model, &options.opening)?;
    if let Some(dir) = options.save_dir {
        session.save_dir = dir;
    }
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| Error::Invalid(format!("cannot start the server's runtime: {e}")))?;
    runtime.block_on(async move {
        let listener = bind(options.port).await?;
        let address = listener.local_addr().map_err(|e| Error::Invalid(format!("the server's address: {e}")))?;
        ready(address, &session);
        let shared = Arc::new(Mutex::new(session));
        tokio::spawn(write_recovery_copies(shared.clone()));
        axum::serve(listener, router(shared)).await.map_err(|e| Error::Invalid(format!("the server stopped: {e}")))
    })
}

/// Listens on `port`, or on the first free port from `DEFAULT_PORT`.
async fn bind(port: Option<u16>) -> Result<tokio::net::TcpListener> {
    let at = |p: u16| SocketAddr::from((Ipv4Addr::LOCALHOST, p));
    match port {
        Some(p) => tokio::net::TcpListener::bind(at(p)).await.map_err(|e| {
            Error::parameter("port", format!("{p} cannot be listened on ({e}): choose another or leave --port out"))
        }),
        None => {
            for p in DEFAULT_PORT..DEFAULT_PORT.saturating_add(100) {
                if let Ok(listener) = tokio::net::TcpListener::bind(at(p)).await {
                    return Ok(listener);
                }
            }
            Err(Error::Invalid(format!(
                "no free port from {DEFAULT_PORT} to {}: give one with --port",
                DEFAULT_PORT + 99
            )))
        }
    }
}

/// Every few seconds, a copy of a changed atlas in the recovery folder: nothing painted is lost if the
/// server stops.
async fn write_recovery_copies(session: Arc<Mutex<Session>>) {
    let mut tick = tokio::time::interval(server::RECOVERY_EVERY);
    loop {
        tick.tick().await;
        let session = session.clone();
        let written = tokio::task::spawn_blocking(move || {
            session.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).write_recovery()
        })
        .await;
        if let Ok(Err(e)) = written {
            eprintln!("warning: the recovery copy was not written: {e}");
        }
    }
}
