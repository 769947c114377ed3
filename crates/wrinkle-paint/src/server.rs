//! The web server: the page (built into the binary), the HTTP API and the WebSocket of docs/paint.md. It
//! only carries messages: every request locks the session and runs on a blocking thread, since rendering
//! and painting are CPU work.

use crate::brush::Brush;
use crate::channels::Channel;
use crate::frames::{encode_frame, FrameFormat};
use crate::session::{Orbit, Session};
use axum::body::Bytes;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::{Path as UrlPath, State};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;
use serde::Deserialize;
use serde_json::{json, Value};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Duration;

pub type Shared = Arc<Mutex<Session>>;

/// How often a changed atlas is copied to the recovery folder.
pub const RECOVERY_EVERY: Duration = Duration::from_secs(5);

/// The page and the API over one session.
pub fn router(session: Shared) -> Router {
    Router::new()
        .route("/", get(|| async { asset("index.html") }))
        .route("/assets/{file}", get(|UrlPath(file): UrlPath<String>| async move { asset(&file) }))
        .route("/api/state", get(state))
        .route("/api/camera", post(camera))
        .route("/api/stroke", post(stroke))
        .route("/api/undo", post(|s: State<Shared>| undo(s, false)))
        .route("/api/redo", post(|s: State<Shared>| undo(s, true)))
        .route("/api/frame.png", get(|s: State<Shared>| frame(s, FrameFormat::Png)))
        .route("/api/frame.jpg", get(|s: State<Shared>| frame(s, FrameFormat::Jpeg)))
        .route("/api/atlas/{file}", get(atlas))
        .route("/api/save", post(save))
        .route("/api/ws", get(websocket))
        .with_state(session)
}

/// Runs `work` on the session on a blocking thread.
async fn with_session<T: Send + 'static>(
    session: &Shared,
    work: impl FnOnce(&mut Session) -> Result<T, Failure> + Send + 'static,
) -> Result<T, Failure> {
    let session = session.clone();
    tokio::task::spawn_blocking(move || {
        let mut s = session.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        work(&mut s)
    })
    .await
    .unwrap_or_else(|e| Err(Failure::internal(format!("the request failed: {e}"))))
}

/// An error answer: 400 for a malformed request, 500 for what went wrong here; a JSON body naming it.
pub struct Failure {
    status: StatusCode,
    message: String,
}

impl Failure {
    fn bad(message: impl Into<String>) -> Failure {
        Failure { status: StatusCode::BAD_REQUEST, message: message.into() }
    }
    fn internal(message: impl Into<String>) -> Failure {
        Failure { status: StatusCode::INTERNAL_SERVER_ERROR, message: message.into() }
    }
}

impl From<wrinkle::Error> for Failure {
    /// The library's errors about what was asked (a parameter, an invalid value) are the client's.
    fn from(e: wrinkle::Error) -> Failure {
        match e {
            wrinkle::Error::Parameter { .. } | wrinkle::Error::Invalid(_) => Failure::bad(e.to_string()),
            other => Failure::internal(other.to_string()),
        }
    }
}

impl IntoResponse for Failure {
    fn into_response(self) -> Response {
        (self.status, axum::Json(json!({ "error": self.message }))).into_response()
    }
}

fn parse<T: for<'de> Deserialize<'de>>(body: &[u8]) -> Result<T, Failure> {
    let body = if body.iter().all(u8::is_ascii_whitespace) { b"{}".as_slice() } else { body };
    serde_json::from_slice(body).map_err(|e| Failure::bad(format!("malformed request: {e}")))
}

fn json_answer(value: impl serde::Serialize) -> Response {
    axum::Json(value).into_response()
}

async fn state(State(session): State<Shared>) -> Result<Response, Failure> {
    with_session(&session, |s| Ok(json_answer(s.state()))).await
}

/// `POST /api/camera`: the orbit, and optionally the view's size.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraRequest {
    yaw: f32,
    pitch: f32,
    distance: f32,
    target: Option<[f32; 3]>,
    width: Option<usize>,
    height: Option<usize>,
}

impl CameraRequest {
    fn apply(self, s: &mut Session) -> Result<(), Failure> {
        let target = self.target.unwrap_or(s.state().camera.target);
        s.set_camera(Orbit { yaw: self.yaw, pitch: self.pitch, distance: self.distance, target })?;
        if self.width.is_some() || self.height.is_some() {
            let state = s.state();
            s.resize(self.width.unwrap_or(state.width), self.height.unwrap_or(state.height))?;
        }
        Ok(())
    }
}

async fn camera(State(session): State<Shared>, body: Bytes) -> Result<Response, Failure> {
    let request: CameraRequest = parse(&body)?;
    with_session(&session, move |s| {
        request.apply(s)?;
        Ok(json_answer(s.state()))
    })
    .await
}

/// `POST /api/stroke`: the brush and its points.
#[derive(Deserialize)]
struct StrokeRequest {
    points: Vec<[f32; 2]>,
    #[serde(flatten)]
    brush: Value,
}

async fn stroke(State(session): State<Shared>, body: Bytes) -> Result<Response, Failure> {
    let request: StrokeRequest = parse(&body)?;
    let brush: Brush =
        serde_json::from_value(request.brush).map_err(|e| Failure::bad(format!("malformed brush: {e}")))?;
    with_session(&session, move |s| {
        let texels = s.stroke(brush, &request.points)?;
        Ok(json_answer(json!({ "texels": texels })))
    })
    .await
}

async fn undo(State(session): State<Shared>, redo: bool) -> Result<Response, Failure> {
    with_session(&session, move |s| Ok(json_answer(json!({ "texels": s.undo(redo) })))).await
}

async fn frame(State(session): State<Shared>, format: FrameFormat) -> Result<Response, Failure> {
    let bytes = with_session(&session, move |s| Ok(encode_frame(s.frame()?, format)?)).await?;
    Ok(([(header::CONTENT_TYPE, format.mime()), (header::CACHE_CONTROL, "no-store")], bytes).into_response())
}

async fn atlas(State(session): State<Shared>, UrlPath(file): UrlPath<String>) -> Result<Response, Failure> {
    let channel = file
        .strip_suffix(".png")
        .and_then(Channel::parse)
        .ok_or_else(|| Failure { status: StatusCode::NOT_FOUND, message: format!("no atlas channel {file}") })?;
    let bytes = with_session(&session, move |s| Ok(s.atlas().png(channel)?)).await?;
    Ok(([(header::CONTENT_TYPE, "image/png"), (header::CACHE_CONTROL, "no-store")], bytes).into_response())
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SaveRequest {
    dir: Option<PathBuf>,
}

async fn save(State(session): State<Shared>, body: Bytes) -> Result<Response, Failure> {
    let request: SaveRequest = parse(&body)?;
    with_session(&session, move |s| Ok(json_answer(s.save(request.dir.as_deref())?))).await
}

/// The built page's files, embedded in the binary.
fn asset(file: &str) -> Response {
    match crate::page::file(file) {
        Some((bytes, mime)) => ([(header::CONTENT_TYPE, mime)], bytes).into_response(),
        None => (StatusCode::NOT_FOUND, "not found").into_response(),
    }
}

async fn websocket(State(session): State<Shared>, upgrade: WebSocketUpgrade) -> Response {
    upgrade.on_upgrade(move |socket| live(socket, session))
}

/// One page's live channel (docs/paint.md, "WebSocket"). A stroke left open when the page goes away is
/// ended, so what it painted is kept and can be undone.
async fn live(mut socket: WebSocket, session: Shared) {
    let state = with_session(&session, |s| {
        let mut state = serde_json::to_value(s.state()).expect("the state serialises");
        state["type"] = "state".into();
        Ok(state.to_string())
    });
    if let Ok(state) = state.await {
        if socket.send(Message::Text(state.into())).await.is_err() {
            return;
        }
    }
    while let Some(Ok(message)) = socket.recv().await {
        let text = match message {
            Message::Text(t) => t.to_string(),
            Message::Close(_) => break,
            _ => continue,
        };
        let answers = match serde_json::from_str::<Value>(&text) {
            Ok(request) => live_request(&session, request).await,
            Err(e) => Err(Failure::bad(format!("malformed message: {e}"))),
        };
        let answers = answers.unwrap_or_else(|f| vec![Answer::Text(json!({"type": "error", "message": f.message}))]);
        for answer in answers {
            let message = match answer {
                Answer::Text(v) => Message::Text(v.to_string().into()),
                Answer::Frame(bytes) => Message::Binary(bytes.into()),
            };
            if socket.send(message).await.is_err() {
                break;
            }
        }
    }
    let _ = with_session(&session, |s| Ok(s.end_stroke())).await;
}

enum Answer {
    Text(Value),
    Frame(Vec<u8>),
}

/// Carries out one message of the live channel: its answers, in order.
async fn live_request(session: &Shared, request: Value) -> Result<Vec<Answer>, Failure> {
    let kind = request.get("type").and_then(Value::as_str).unwrap_or_default().to_owned();
    let without_type = |mut v: Value| {
        if let Some(o) = v.as_object_mut() {
            o.remove("type");
        }
        v
    };
    let frame = |s: &mut Session, format: FrameFormat| -> Result<Answer, Failure> {
        Ok(Answer::Frame(encode_frame(s.frame()?, format)?))
    };
    match kind.as_str() {
        "camera" => {
            let camera: CameraRequest = serde_json::from_value(without_type(request))
                .map_err(|e| Failure::bad(format!("malformed camera: {e}")))?;
            with_session(session, move |s| {
                camera.apply(s)?;
                Ok(vec![frame(s, FrameFormat::Jpeg)?])
            })
            .await
        }
        "stroke_begin" => {
            let brush: Brush = serde_json::from_value(without_type(request))
                .map_err(|e| Failure::bad(format!("malformed brush: {e}")))?;
            with_session(session, move |s| {
                s.begin_stroke(brush)?;
                Ok(Vec::new())
            })
            .await
        }
        "stroke_point" => {
            let coordinate = |name: &str| {
                request
                    .get(name)
                    .and_then(Value::as_f64)
                    .map(|v| v as f32)
                    .ok_or_else(|| Failure::bad(format!("stroke_point needs a number {name}")))
            };
            let (x, y) = (coordinate("x")?, coordinate("y")?);
            with_session(session, move |s| {
                s.stroke_to(x, y)?;
                Ok(vec![frame(s, FrameFormat::Jpeg)?])
            })
            .await
        }
        "stroke_end" | "undo" | "redo" => {
            with_session(session, move |s| {
                let texels = match kind.as_str() {
                    "stroke_end" => s.end_stroke(),
                    k => s.undo(k == "redo"),
                };
                let state = s.state();
                Ok(vec![
                    Answer::Text(json!({"type": "stroke", "texels": texels, "undo": state.undo, "redo": state.redo})),
                    frame(s, FrameFormat::Png)?,
                ])
            })
            .await
        }
        "frame" => {
            let lossless = request.get("lossless").and_then(Value::as_bool).unwrap_or(true);
            let format = if lossless { FrameFormat::Png } else { FrameFormat::Jpeg };
            with_session(session, move |s| Ok(vec![frame(s, format)?])).await
        }
        "" => Err(Failure::bad("a message needs a \"type\"")),
        other => Err(Failure::bad(format!(
            "unknown message type \"{other}\" (camera, stroke_begin, stroke_point, stroke_end, undo, redo, frame)"
        ))),
    }
}
