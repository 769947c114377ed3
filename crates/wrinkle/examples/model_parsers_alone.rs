//! The time the model parsers wrinkle uses take alone, for BENCHMARKS.md's load times: `tobj` with the
//! options wrinkle's OBJ loader passes, and `gltf::import` (buffers and images decoded), median of three.
//! Usage: cargo run --release -p wrinkle --example model_parsers_alone -- MODEL.obj|.glb|.gltf ...

use std::path::Path;
use std::time::Instant;

fn main() {
    let files: Vec<String> = std::env::args().skip(1).collect();
    if files.is_empty() {
        eprintln!("usage: model_parsers_alone MODEL.obj|.glb|.gltf ...");
        std::process::exit(2);
    }
    for file in files {
        let path = Path::new(&file);
        let obj = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj"));
        let mut ms: Vec<f64> = (0..3)
            .map(|_| {
                let t = Instant::now();
                let triangles = if obj { tobj_alone(path) } else { gltf_alone(path) };
                let elapsed = t.elapsed().as_secs_f64() * 1e3;
                eprintln!("{file}: {triangles} triangles in {elapsed:.0} ms");
                elapsed
            })
            .collect();
        ms.sort_by(f64::total_cmp);
        println!("{file}: {} alone, median of 3: {:.0} ms", if obj { "tobj" } else { "gltf::import" }, ms[1]);
    }
}

fn tobj_alone(path: &Path) -> usize {
    let options = tobj::LoadOptions { single_index: true, triangulate: true, ..tobj::LoadOptions::default() };
    let (models, _) = tobj::load_obj(path, &options).expect("a readable OBJ");
    models.iter().map(|m| m.mesh.indices.len() / 3).sum()
}

fn gltf_alone(path: &Path) -> usize {
    let (document, buffers, _images) = gltf::import(path).expect("a readable glTF");
    let mut triangles = 0;
    for mesh in document.meshes() {
        for primitive in mesh.primitives() {
            let reader = primitive.reader(|b| Some(&buffers[b.index()]));
            let _positions: Vec<[f32; 3]> = reader.read_positions().expect("positions").collect();
            triangles += reader.read_indices().map_or(0, |i| i.into_u32().count()) / 3;
        }
    }
    triangles
}
