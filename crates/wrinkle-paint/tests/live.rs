//! The live channel (WebSocket `/api/ws`) against a real server on a loopback port: a stroke's frames,
//! malformed messages answered without closing the channel, and a page that goes away mid-stroke.

use futures_util::{SinkExt, StreamExt};
use std::path::Path;
use std::sync::{Arc, Mutex};
use tokio_tungstenite::tungstenite::Message;
use wrinkle_paint::{Channel, Opening, Orbit, Session};

async fn serve() -> (String, Arc<Mutex<Session>>) {
    let session = tokio::task::spawn_blocking(|| {
        let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/paint_sphere.toml");
        let mut s =
            Session::open(&scene, &Opening { atlas_size: 128, view: (320, 240), ..Opening::default() }).unwrap();
        s.set_camera(Orbit { yaw: 0.0, pitch: 0.0, distance: 4.0, target: [0.0; 3] }).unwrap();
        s
    })
    .await
    .unwrap();
    let shared = Arc::new(Mutex::new(session));
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let address = listener.local_addr().unwrap();
    let router = wrinkle_paint::router(shared.clone());
    tokio::spawn(async move { axum::serve(listener, router).await });
    (format!("ws://{address}/api/ws"), shared)
}

type Socket = tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

/// The next message, text or binary, within ten seconds.
async fn next(socket: &mut Socket) -> Message {
    let wait = tokio::time::timeout(std::time::Duration::from_secs(10), socket.next());
    wait.await.expect("an answer within 10 s").expect("the channel is open").expect("a message")
}

async fn send(socket: &mut Socket, text: &str) {
    socket.send(Message::Text(text.into())).await.unwrap();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn strokes_answer_with_frames_and_bad_messages_with_errors() {
    let (url, shared) = serve().await;
    let (mut socket, _) = tokio_tungstenite::connect_async(&url).await.unwrap();
    let Message::Text(state) = next(&mut socket).await else { panic!("the state comes first") };
    let state: serde_json::Value = serde_json::from_str(&state).unwrap();
    assert_eq!((state["type"].as_str(), state["width"].as_u64()), (Some("state"), Some(320)));
    // Malformed messages: each answered by an error naming the fault; the channel stays open.
    for (message, fault) in [
        ("{not json", "malformed message"),
        (r#"{"type": "fly"}"#, "unknown message type"),
        (r#"{"type": "stroke_point", "x": 5}"#, "y"),
        (r#"{"type": "stroke_begin", "radius": -3, "color": [1, 0, 0]}"#, "radius"),
        (r#"{"type": "camera", "yaw": 0, "pitch": 0}"#, "distance"),
    ] {
        send(&mut socket, message).await;
        let Message::Text(answer) = next(&mut socket).await else { panic!("{message}: an error, not a frame") };
        assert!(answer.contains("\"error\"") && answer.contains(fault), "{message}: {answer}");
    }
    // A stroke: a JPEG frame per point, then its count and a PNG frame.
    send(&mut socket, r#"{"type": "stroke_begin", "radius": 20, "color": [0, 1, 0]}"#).await;
    for x in [140, 160, 180] {
        send(&mut socket, &format!(r#"{{"type": "stroke_point", "x": {x}, "y": 120}}"#)).await;
        let Message::Binary(frame) = next(&mut socket).await else { panic!("a frame") };
        assert_eq!(&frame[..2], &[0xFF, 0xD8], "a JPEG while dragging");
    }
    send(&mut socket, r#"{"type": "stroke_end"}"#).await;
    let Message::Text(done) = next(&mut socket).await else { panic!("the stroke's count") };
    let done: serde_json::Value = serde_json::from_str(&done).unwrap();
    assert!(done["texels"].as_u64().unwrap() > 50, "{done}");
    let Message::Binary(frame) = next(&mut socket).await else { panic!("a frame") };
    assert_eq!(&frame[..4], b"\x89PNG", "a lossless frame at rest");
    assert_eq!(shared.lock().unwrap().state().undo, 1);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_page_that_goes_away_mid_stroke_keeps_what_it_painted() {
    let (url, shared) = serve().await;
    let start = shared.lock().unwrap().atlas().codes(Channel::Color).to_vec();
    let (mut socket, _) = tokio_tungstenite::connect_async(&url).await.unwrap();
    next(&mut socket).await;
    send(&mut socket, r#"{"type": "stroke_begin", "radius": 20, "color": [0, 0, 1]}"#).await;
    send(&mut socket, r#"{"type": "stroke_point", "x": 160, "y": 120}"#).await;
    next(&mut socket).await;
    drop(socket);
    // The server ends the stroke when the channel closes: kept, and one undo step.
    let mut undo = 0;
    for _ in 0..100 {
        undo = shared.lock().unwrap().state().undo;
        if undo == 1 {
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(50)).await;
    }
    assert_eq!(undo, 1, "the stroke was ended and kept");
    let mut s = shared.lock().unwrap();
    assert_ne!(s.atlas().codes(Channel::Color), start.as_slice());
    s.undo(false);
    assert_eq!(s.atlas().codes(Channel::Color), start.as_slice());
}
