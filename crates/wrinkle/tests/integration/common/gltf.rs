//! glTF 2.0 files written from the specification (not through the `gltf` crate the loader uses): one
//! binary buffer of little-endian accessors, as a .gltf with its buffer in a data URI or a file, or as a GLB
//! container (12-byte header, a JSON chunk, a BIN chunk, each padded to four bytes).

/// One mesh primitive's data; `image` is an embedded PNG the material's textures read.
#[derive(Clone, Debug, Default)]
pub struct Primitive {
    pub positions: Vec<[f32; 3]>,
    pub normals: Option<Vec<[f32; 3]>>,
    /// glTF's convention: (0, 0) at the top left of the image.
    pub uvs: Option<Vec<[f32; 2]>>,
    /// TEXCOORD_1, as `uvs`.
    pub uvs1: Option<Vec<[f32; 2]>>,
    pub tangents: Option<Vec<[f32; 4]>>,
    pub indices: Vec<u32>,
}

/// How the file is laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// .gltf with the buffer as a base64 data URI.
    Embedded,
    /// .gltf beside a .bin file (returned as the second output).
    Separate,
    /// One .glb.
    Binary,
}

/// A file of one node (with `matrix`, column-major, when given) holding one mesh of `primitive`, whose
/// material has `material` as its JSON (it may name texture 0, which reads `png`).
pub struct File {
    pub primitive: Primitive,
    pub matrix: Option<[f32; 16]>,
    pub material: String,
    pub png: Option<Vec<u8>>,
}

impl File {
    /// The bytes of the main file and, for `Layout::Separate`, of the .bin named `bin_name`.
    pub fn write(&self, layout: Layout, bin_name: &str) -> (Vec<u8>, Vec<u8>) {
        let mut bin = Vec::new();
        let mut views = Vec::new();
        let mut accessors = Vec::new();
        let mut attributes = Vec::new();
        let mut push = |bytes: Vec<u8>, count: usize, kind: &str, component: u32, target: Option<u32>| {
            while bin.len() % 4 != 0 {
                bin.push(0);
            }
            let target = target.map_or(String::new(), |t| format!(", \"target\": {t}"));
            views.push(format!(
                "{{\"buffer\": 0, \"byteOffset\": {}, \"byteLength\": {}{target}}}",
                bin.len(),
                bytes.len()
            ));
            bin.extend_from_slice(&bytes);
            accessors.push((views.len() - 1, count, kind.to_string(), component));
            accessors.len() - 1
        };
        let floats = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
        let p = &self.primitive;
        let flat3: Vec<f32> = p.positions.iter().flatten().copied().collect();
        let pos = push(floats(&flat3), p.positions.len(), "VEC3", 5126, Some(34962));
        attributes.push(format!("\"POSITION\": {pos}"));
        if let Some(n) = &p.normals {
            let k = push(floats(&n.iter().flatten().copied().collect::<Vec<_>>()), n.len(), "VEC3", 5126, Some(34962));
            attributes.push(format!("\"NORMAL\": {k}"));
        }
        for (set, uvs) in [&p.uvs, &p.uvs1].into_iter().enumerate() {
            if let Some(t) = uvs {
                let flat: Vec<f32> = t.iter().flatten().copied().collect();
                let k = push(floats(&flat), t.len(), "VEC2", 5126, Some(34962));
                attributes.push(format!("\"TEXCOORD_{set}\": {k}"));
            }
        }
        if let Some(t) = &p.tangents {
            let k = push(floats(&t.iter().flatten().copied().collect::<Vec<_>>()), t.len(), "VEC4", 5126, Some(34962));
            attributes.push(format!("\"TANGENT\": {k}"));
        }
        let indices: Vec<u8> = p.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let idx = push(indices, p.indices.len(), "SCALAR", 5125, Some(34963));
        let image = self.png.as_ref().map(|png| push(png.clone(), 0, "", 0, None));
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        // The position accessor must carry its bounds.
        let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
        for q in &p.positions {
            for c in 0..3 {
                lo[c] = lo[c].min(q[c]);
                hi[c] = hi[c].max(q[c]);
            }
        }
        let accessor_json: Vec<String> = accessors
            .iter()
            .enumerate()
            .filter(|(_, a)| a.3 != 0)
            .map(|(k, (view, count, kind, component))| {
                let bounds = if k == pos { format!(", \"min\": {lo:?}, \"max\": {hi:?}") } else { String::new() };
                format!("{{\"bufferView\": {view}, \"componentType\": {component}, \"count\": {count}, \"type\": \"{kind}\"{bounds}}}")
            })
            .collect();
        let uri = match layout {
            Layout::Embedded => format!(", \"uri\": \"data:application/octet-stream;base64,{}\"", base64(&bin)),
            Layout::Separate => format!(", \"uri\": \"{bin_name}\""),
            Layout::Binary => String::new(),
        };
        let images = match image {
            Some(view) => format!(
                ", \"images\": [{{\"bufferView\": {}, \"mimeType\": \"image/png\"}}], \"textures\": [{{\"source\": 0}}]",
                accessors[view].0
            ),
            None => String::new(),
        };
        let matrix = self.matrix.map_or(String::new(), |m| format!(", \"matrix\": {m:?}"));
        let json = format!(
            "{{\"asset\": {{\"version\": \"2.0\"}}, \"scene\": 0, \"scenes\": [{{\"nodes\": [0]}}], \
             \"nodes\": [{{\"mesh\": 0{matrix}}}], \
             \"meshes\": [{{\"primitives\": [{{\"attributes\": {{{}}}, \"indices\": {idx}, \"material\": 0}}]}}], \
             \"materials\": [{}], \"accessors\": [{}], \"bufferViews\": [{}], \
             \"buffers\": [{{\"byteLength\": {}{uri}}}]{images}}}",
            attributes.join(", "),
            self.material,
            accessor_json.join(", "),
            views.join(", "),
            bin.len(),
        );
        match layout {
            Layout::Embedded => (json.into_bytes(), Vec::new()),
            Layout::Separate => (json.into_bytes(), bin),
            Layout::Binary => (glb(json.into_bytes(), bin), Vec::new()),
        }
    }
}

/// The GLB container: header, JSON chunk padded with spaces, BIN chunk padded with zeros.
fn glb(mut json: Vec<u8>, mut bin: Vec<u8>) -> Vec<u8> {
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// RFC 4648 base64 with padding.
fn base64(data: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(data.len().div_ceil(3) * 4);
    for chunk in data.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// A 2x2 PNG of one colour, as the bytes of its file.
pub fn png_of(dir: &std::path::Path, rgb: [u8; 3]) -> Vec<u8> {
    let path = dir.join(format!("texel_{}_{}_{}.png", rgb[0], rgb[1], rgb[2]));
    wrinkle::image::io::write_png_rgb8(&path, 2, 2, &rgb.repeat(4)).expect("write png");
    std::fs::read(&path).expect("read png")
}
