//! Texture atlases laid out for meshes (geometry::unwrap), checked by rasterising the result at the atlas's
//! resolution here, independently of the unwrapper: no two triangles cover one texel centre, charts keep
//! their gutter apart, every (u,v) lies in the image, and the stretch is the flattening's bound.

use glam::Vec2;
use std::collections::HashMap;
use std::path::Path;
use wrinkle::geometry::unwrap::{unwrap, UnwrapOptions};
use wrinkle::geometry::{Primitive, TriangleMesh};
use wrinkle::Scene;

fn teapot() -> TriangleMesh {
    let scene = Scene::parse(
        "[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n[[object]]\nshape = \"mesh\"\nfile = \"models/teapot.obj\"\n",
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes"),
    )
    .unwrap();
    let mut mesh = TriangleMesh::default();
    for p in scene.objects[0].shape.primitives() {
        let Primitive::Mesh(m) = p else { panic!("a mesh") };
        mesh.append(&m);
    }
    mesh
}

/// Charts as the result shows them: triangles joined where they share a corner, the same position at the
/// same (u,v) (charts lie apart in the image; a model may split a vertex within a chart for its normals).
fn charts_of(mesh: &TriangleMesh) -> Vec<usize> {
    let uvs = mesh.uvs(0).unwrap();
    let mut corner_ids: HashMap<[u32; 5], usize> = HashMap::new();
    let corner = |k: u32, ids: &mut HashMap<[u32; 5], usize>| {
        let (p, uv) = (mesh.positions[k as usize], uvs[k as usize]);
        let key = [p.x, p.y, p.z, uv.x, uv.y].map(f32::to_bits);
        let next = ids.len();
        *ids.entry(key).or_insert(next)
    };
    let corners: Vec<[usize; 3]> = mesh.triangles.iter().map(|t| t.map(|k| corner(k, &mut corner_ids))).collect();
    let mut parent: Vec<usize> = (0..corner_ids.len()).collect();
    fn root(p: &mut [usize], mut k: usize) -> usize {
        while p[k] != k {
            p[k] = p[p[k]];
            k = p[k];
        }
        k
    }
    for t in &corners {
        for c in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[c]));
            parent[a] = b;
        }
    }
    corners.iter().map(|t| root(&mut parent, t[0])).collect()
}

#[test]
fn the_teapot_gets_non_overlapping_charts_with_their_gutters() {
    let (size, gutter) = (1024, 10);
    let source = teapot();
    let (meshes, report) = unwrap(&[&source], UnwrapOptions { size, gutter, max_angle: 45.0 }).unwrap();
    let mesh = &meshes[0];
    mesh.validate().unwrap();
    assert_eq!(mesh.triangles.len(), source.triangles.len());
    println!("teapot atlas: {report:?}");
    let uvs = mesh.uvs(0).unwrap();
    assert!(uvs.iter().all(|uv| (0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y)));
    // Positions are the source's: each new vertex is a copy.
    for (t, s) in mesh.triangles.iter().zip(&source.triangles) {
        for c in 0..3 {
            assert_eq!(mesh.positions[t[c] as usize], source.positions[s[c] as usize]);
        }
    }
    let chart = charts_of(mesh);
    let distinct: std::collections::HashSet<_> = chart.iter().collect();
    assert_eq!(distinct.len(), report.charts, "charts seen in the result");
    // Rasterise every triangle at texel centres: which chart covers each texel, and no texel twice.
    let mut owner: Vec<Option<usize>> = vec![None; size * size];
    let texel = |uv: Vec2| Vec2::new(uv.x * size as f32, (1.0 - uv.y) * size as f32);
    for (f, t) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = t.map(|k| texel(uvs[k as usize]));
        let area = (b - a).perp_dot(c - a);
        if area.abs() < 1e-9 {
            continue;
        }
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        for y in (lo.y.floor() as usize)..=(hi.y.ceil() as usize).min(size - 1) {
            for x in (lo.x.floor() as usize)..=(hi.x.ceil() as usize).min(size - 1) {
                let q = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let inside =
                    [(a, b), (b, c), (c, a)].iter().all(|(p, r)| (*r - *p).perp_dot(q - *p) * area.signum() > 1e-4);
                if inside {
                    assert!(owner[y * size + x].is_none(), "texel ({x}, {y}) is covered twice (triangle {f})");
                    owner[y * size + x] = Some(chart[f]);
                }
            }
        }
    }
    // No texel of another chart within the gutter (less a texel each side for where centres fall).
    let reach = (gutter - 2) as i64;
    let mut nearest = HashMap::new();
    for y in 0..size as i64 {
        for x in 0..size as i64 {
            let Some(c) = owner[(y * size as i64 + x) as usize] else { continue };
            for dy in -reach..=reach {
                for dx in -reach..=reach {
                    let (u, v) = (x + dx, y + dy);
                    if u < 0 || v < 0 || u >= size as i64 || v >= size as i64 {
                        continue;
                    }
                    if let Some(d) = owner[(v * size as i64 + u) as usize] {
                        assert!(d == c, "charts {c} and {d} meet within the gutter at ({x}, {y}) and ({u}, {v})");
                    }
                }
            }
            nearest.entry(c).or_insert((x, y));
        }
    }
    let covered = owner.iter().filter(|o| o.is_some()).count() as f32 / (size * size) as f32;
    assert!((covered - report.utilisation).abs() < 0.02, "covered {covered}, reported {report:?}");
    assert!(report.utilisation > 0.25, "{report:?}");
    // Planar projection within 45 degrees: a face's anisotropy is at most 1 / cos 45.
    assert!(report.stretch_max <= 1.0 / 45f32.to_radians().cos() + 1e-3, "{report:?}");
    assert!(report.stretch_mean >= 1.0 && report.stretch_mean < 1.2, "{report:?}");
}
