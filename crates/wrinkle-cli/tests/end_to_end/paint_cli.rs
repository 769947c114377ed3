//! `wrinkle paint` from the command line: what it refuses before serving (a model that does not load, a
//! busy port), and its in-process benchmark's figures. The page and the API are tested in
//! crates/wrinkle-paint/tests.

use crate::common::{assert_one_error, wrinkle, Scratch};

fn sphere_scene() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/paint_sphere.toml").to_string()
}

#[test]
fn paint_refuses_a_model_that_does_not_load_and_a_busy_port() {
    let scratch = Scratch::new("paint");
    let missing = scratch.input("no_such_model.obj");
    assert_one_error(&wrinkle(&["paint", &missing]), 2, &["no_such_model.obj"], &scratch);
    let broken = scratch.write_input("broken.obj", "v 0 0 0\nf 1 2 3\n");
    assert_one_error(&wrinkle(&["paint", &broken]), 2, &["broken.obj"], &scratch);
    // A port something else listens on: the one named is refused, not another taken silently.
    let busy = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = busy.local_addr().unwrap().port().to_string();
    assert_one_error(&wrinkle(&["paint", &sphere_scene(), "--port", &port]), 2, &["--port", &port], &scratch);
    assert_one_error(&wrinkle(&["paint", &sphere_scene(), "--atlas-size", "3"]), 2, &["--atlas-size"], &scratch);
}

#[test]
fn paint_bench_reports_frames_and_dabs() {
    let run = wrinkle(&["paint", &sphere_scene(), "--bench", "3", "--view", "160x120", "--atlas-size", "64"]);
    assert_eq!(run.code, 0, "{run:#?}");
    for line in ["orbit frame", "dab of 30 px"] {
        let row =
            run.stdout.lines().find(|l| l.starts_with(line)).unwrap_or_else(|| panic!("no {line} row: {}", run.stdout));
        let median: f64 = row.split_whitespace().skip_while(|w| *w != "median").nth(1).unwrap().parse().unwrap();
        assert!(median > 0.0 && median < 10_000.0, "{row}");
    }
}
