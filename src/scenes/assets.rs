//! The files a scene file names (Wavefront OBJ meshes, PNG images) and the ones raypool makes
//! itself (a terrain mesh, a planet's image): loaded once, when the scene file is read, and
//! refused with one line when they are missing, malformed, too large or outside the scene
//! file's folder.

use std::collections::BTreeMap;
use std::io::{BufRead, Read};
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::error::io_reason;
use crate::scenes::checks::{REAL, check, representable};
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::shading::perlin::Perlin;
use crate::tracer::shading::texture::ImageTexture;
use crate::tracer::world::mesh::Mesh;

/// The largest OBJ or image file a scene may name, in bytes (256 MiB: 3 million triangles of
/// OBJ text). Larger files are refused before a byte is read.
pub const MAX_ASSET_BYTES: u64 = 256 << 20;

/// The most pixels an image texture may have (64 million: 1 GiB as linear RGB).
const MAX_IMAGE_PIXELS: u64 = 64 << 20;

/// A mesh raypool generates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum GeneratedMesh {
    /// A square of Perlin-noise hills: `2·cells²` triangles, `size` wide, `height` tall.
    Terrain {
        /// Cells per side, 1 to 1024.
        cells: u32,
        /// Side length.
        size: f64,
        /// Height of the tallest hills.
        height: f64,
        /// Seed of the hills' noise.
        seed: u64,
    },
}

impl GeneratedMesh {
    /// Checks the numbers.
    pub fn check(&self) -> Result<(), String> {
        let GeneratedMesh::Terrain { cells, size, height, .. } = *self;
        check((1..=1024).contains(&cells), || format!("terrain cells must be 1 to 1024, got {cells}"))?;
        check(representable(size) && size > 0.0, || {
            format!("terrain size must be finite (as {REAL}) and > 0, got {size}")
        })?;
        check(representable(height), || format!("terrain height must be finite (as {REAL}), got {height}"))
    }

    /// The mesh.
    pub fn generate(&self) -> Mesh {
        let GeneratedMesh::Terrain { cells, size, height, seed } = *self;
        let noise = Perlin::new(seed);
        let n = cells as usize + 1;
        let step = size / cells as f64;
        let ground = |i: usize, j: usize| {
            let (x, z) = (-0.5 * size + i as f64 * step, -0.5 * size + j as f64 * step);
            let p = Vec3::new(x as Real, 0.0, z as Real) * (4.0 / size as Real);
            let hills = (0..5).map(|o| noise.noise(p * (1 << o) as Real) / (1 << o) as Real).sum::<Real>();
            Vec3::new(x as Real, height as Real * hills, z as Real)
        };
        let positions: Vec<Vec3> = (0..n * n).map(|k| ground(k / n, k % n)).collect();
        let at = |i: usize, j: usize| positions[i.min(n - 1) * n + j.min(n - 1)];
        let normals = (0..n * n)
            .map(|k| {
                let (i, j) = (k / n, k % n);
                let dx = at(i + 1, j) - at(i.saturating_sub(1), j);
                let dz = at(i, j + 1) - at(i, j.saturating_sub(1));
                dz.cross(dx).normalize()
            })
            .collect();
        let uvs =
            (0..n * n).map(|k| [(k / n) as Real / cells as Real, (k % n) as Real / cells as Real]).collect();
        let index = |i: usize, j: usize| (i * n + j) as u32;
        let triangles = (0..cells as usize * cells as usize)
            .flat_map(|c| {
                let (i, j) = (c / cells as usize, c % cells as usize);
                [
                    [index(i, j), index(i, j + 1), index(i + 1, j)],
                    [index(i + 1, j), index(i, j + 1), index(i + 1, j + 1)],
                ]
            })
            .collect();
        Mesh::new(positions, normals, uvs, triangles).expect("a terrain's triangles all have area")
    }
}

/// What a scene's files became: meshes and images by path.
#[derive(Clone, Debug, Default)]
pub struct Assets {
    meshes: BTreeMap<(String, u64), Arc<Mesh>>,
    images: BTreeMap<String, ImageTexture>,
}

impl Assets {
    /// Loads the OBJ files `meshes` names (`(mesh number, path, scale)`) and the `images`,
    /// relative to `folder`; `None` when the scene came from no file, which may then name none.
    pub fn load(
        folder: Option<&Path>,
        meshes: &[(usize, &str, Option<f64>)],
        images: &[&str],
    ) -> Result<Assets, String> {
        let mut assets = Assets::default();
        for &(at, obj, scale) in meshes {
            let scale = scale.unwrap_or(1.0);
            let key = (obj.to_owned(), scale.to_bits());
            if let std::collections::btree_map::Entry::Vacant(slot) = assets.meshes.entry(key) {
                let path = inside(folder, obj).map_err(|e| format!("mesh #{at}: {e}"))?;
                let mesh = load_obj(&path, scale).map_err(|e| format!("mesh #{at}: '{obj}': {e}"))?;
                slot.insert(Arc::new(mesh));
            }
        }
        for &path in images {
            if !assets.images.contains_key(path) {
                let file = inside(folder, path)?;
                let image = load_image(&file).map_err(|e| format!("image '{path}': {e}"))?;
                assets.images.insert(path.to_owned(), image);
            }
        }
        Ok(assets)
    }

    /// The mesh of a checked `[[mesh]]`: its loaded `obj`, or the mesh it `generate`s, at
    /// `scale`.
    pub fn mesh(&self, obj: Option<&str>, generate: Option<&GeneratedMesh>, scale: Option<f64>) -> Arc<Mesh> {
        match (obj, generate) {
            (Some(obj), _) => self.meshes[&(obj.to_owned(), scale.unwrap_or(1.0).to_bits())].clone(),
            (None, Some(generated)) => Arc::new(match scale {
                None => generated.generate(),
                Some(factor) => generated.generate().scaled(factor as Real),
            }),
            (None, None) => unreachable!("checked: obj or generate"),
        }
    }

    /// A mesh of loose triangles, three corners each.
    pub fn soup(&self, corners: Vec<Vec3>) -> Mesh {
        let triangles = (0..corners.len() as u32 / 3).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
        Mesh::new(corners, Vec::new(), Vec::new(), triangles).expect("checked: no degenerate triangle")
    }

    /// The image of a checked texture: a loaded file, or one raypool makes.
    pub fn image(&self, path: Option<&str>, builtin: Option<&str>) -> ImageTexture {
        match (path, builtin) {
            (Some(path), _) => self.images[path].clone(),
            (None, Some(_)) => planet(),
            (None, None) => unreachable!("checked: path or builtin"),
        }
    }
}

/// The names of the images raypool makes.
pub const BUILTIN_IMAGES: &[&str] = &["planet"];

/// `name` resolved in `folder`, refused if the scene has no folder, if it is absolute or
/// climbs out (`..`), or if it leads out through a link.
fn inside(folder: Option<&Path>, name: &str) -> Result<PathBuf, String> {
    let folder =
        folder.ok_or_else(|| format!("'{name}': a scene that names files must be read from a file"))?;
    let relative = Path::new(name);
    let climbs = relative.components().any(|c| !matches!(c, Component::Normal(_) | Component::CurDir));
    check(!climbs, || format!("'{name}' leaves the scene file's folder (only paths inside it are read)"))?;
    let path = folder.join(relative);
    let real = path.canonicalize().map_err(|e| format!("cannot read '{name}': {}", io_reason(&e)))?;
    let home =
        folder.canonicalize().map_err(|e| format!("cannot read the scene's folder: {}", io_reason(&e)))?;
    check(real.starts_with(&home), || format!("'{name}' leads out of the scene file's folder"))?;
    Ok(real)
}

/// At most [`MAX_ASSET_BYTES`] of `path`; larger files are refused unread.
fn read_capped(path: &Path) -> Result<Vec<u8>, String> {
    let cannot = |e: std::io::Error| format!("cannot read it: {}", io_reason(&e));
    let file = std::fs::File::open(path).map_err(cannot)?;
    let too_large = || format!("larger than {} MiB: refused", MAX_ASSET_BYTES >> 20);
    if file.metadata().map_err(cannot)?.len() > MAX_ASSET_BYTES {
        return Err(too_large());
    }
    let mut bytes = Vec::new();
    file.take(MAX_ASSET_BYTES + 1).read_to_end(&mut bytes).map_err(cannot)?;
    check(bytes.len() as u64 <= MAX_ASSET_BYTES, too_large)?;
    Ok(bytes)
}

/// Every object of an OBJ file as one mesh (faces triangulated), vertices times `scale`.
fn load_obj(path: &Path, scale: f64) -> Result<Mesh, String> {
    let bytes = read_capped(path)?;
    let options = tobj::LoadOptions { single_index: true, triangulate: true, ..Default::default() };
    let mut reader = Counted { rest: &bytes, lines: 0, last: b'\n' };
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed) // materials come from the scene file, not .mtl
    })
    .map_err(|e| obj_error(&bytes, &reader, &e))?;
    let (mut positions, mut normals, mut uvs, mut triangles) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let with_normals = models.iter().all(|m| !m.mesh.normals.is_empty());
    let with_uvs = models.iter().all(|m| !m.mesh.texcoords.is_empty());
    for model in &models {
        let mesh = &model.mesh;
        let first = positions.len() as u32;
        let point = |c: &[f32]| Vec3::new(c[0] as Real, c[1] as Real, c[2] as Real);
        positions.extend(mesh.positions.chunks_exact(3).map(|c| point(c) * scale as Real));
        if with_normals {
            normals.extend(mesh.normals.chunks_exact(3).map(point));
        }
        if with_uvs {
            uvs.extend(mesh.texcoords.chunks_exact(2).map(|c| [c[0] as Real, c[1] as Real]));
        }
        triangles.extend(mesh.indices.chunks_exact(3).map(|t| [first + t[0], first + t[1], first + t[2]]));
    }
    Mesh::new(positions, normals, uvs, triangles)
}

/// The OBJ text as tobj reads it, counting the lines it has taken: tobj reads line by line and
/// stops at the first it cannot parse, but its errors name no line.
struct Counted<'a> {
    rest: &'a [u8],
    /// Line ends taken so far.
    lines: usize,
    /// The last byte taken (`\n` before the first).
    last: u8,
}

impl Read for Counted<'_> {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        let n = out.len().min(self.rest.len());
        out[..n].copy_from_slice(&self.rest[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl BufRead for Counted<'_> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        Ok(self.rest)
    }

    fn consume(&mut self, n: usize) {
        let (taken, rest) = self.rest.split_at(n);
        self.lines += taken.iter().filter(|&&b| b == b'\n').count();
        self.last = taken.last().copied().unwrap_or(self.last);
        self.rest = rest;
    }
}

/// tobj's `error` on `bytes` as one line naming the line of the file it concerns, and quoting
/// it: the line tobj stopped at, or for an index out of bounds (found only when an object
/// ends) the first face whose index is.
fn obj_error(bytes: &[u8], reader: &Counted, error: &tobj::LoadError) -> String {
    use tobj::LoadError::{FaceNormalOutOfBounds, FaceTexCoordOutOfBounds, FaceVertexOutOfBounds, ReadError};
    let what = match error {
        ReadError => "not UTF-8 text, so not an OBJ file".to_owned(),
        _ => format!("not a valid OBJ file ({error})"),
    };
    let stopped = reader.lines + usize::from(reader.last != b'\n');
    let line = match error {
        FaceVertexOutOfBounds | FaceTexCoordOutOfBounds | FaceNormalOutOfBounds => face_out_of_bounds(bytes),
        _ => Some(stopped),
    };
    let Some(n) = line.filter(|&n| n >= 1) else { return what };
    let text = bytes.split(|&b| b == b'\n').nth(n - 1).unwrap_or_default();
    let whole = String::from_utf8_lossy(text);
    let mut quoted: String = whole.trim_end().chars().take(60).collect();
    if whole.trim_end().chars().count() > 60 {
        quoted += "…";
    }
    format!("line {n}: {what}: {quoted:?}")
}

/// The line of the first face (`f`, `l`) whose vertex, texture or normal index is outside
/// what the file holds when its object ends (the next `o` or `g`, or the end), as tobj checks.
fn face_out_of_bounds(bytes: &[u8]) -> Option<usize> {
    let text = String::from_utf8_lossy(bytes);
    let mut counts = [0i64; 3]; // v, vt, vn read so far
    let mut pending: Vec<(usize, [i64; 3], &str)> = Vec::new(); // faces of the open object
    let outside = |counts: &[i64; 3], (_, then, face): &(usize, [i64; 3], &str)| {
        face.split_whitespace().skip(1).any(|corner| {
            corner.split('/').enumerate().take(3).any(|(k, index)| match index.parse::<i64>() {
                Ok(i) if i < 0 => then[k] + i < 0 || then[k] + i >= counts[k],
                Ok(i) => i == 0 || i > counts[k],
                Err(_) => false,
            })
        })
    };
    for (k, line) in text.lines().enumerate() {
        match line.split_whitespace().next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("f" | "l") => pending.push((k + 1, counts, line)),
            Some("o" | "g") => {
                if let Some(face) = pending.iter().find(|f| outside(&counts, f)) {
                    return Some(face.0);
                }
                pending.clear();
            }
            _ => {}
        }
    }
    pending.iter().find(|f| outside(&counts, f)).map(|f| f.0)
}

/// A PNG (or any format the build reads) as linear RGB.
fn load_image(path: &Path) -> Result<ImageTexture, String> {
    let bytes = read_capped(path)?;
    let reader = image::ImageReader::new(std::io::Cursor::new(&bytes[..]))
        .with_guessed_format()
        .map_err(|e| format!("cannot read it: {e}"))?;
    let (width, height) = reader.into_dimensions().map_err(|e| format!("not an image ({e})"))?;
    check(u64::from(width) * u64::from(height) <= MAX_IMAGE_PIXELS, || {
        format!("{width} × {height} is more than {} million pixels", MAX_IMAGE_PIXELS >> 20)
    })?;
    let decoded = image::load_from_memory(&bytes).map_err(|e| format!("not an image ({e})"))?.to_rgb8();
    let linear = |c: u8| {
        let c = f64::from(c) / 255.0;
        (if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }) as Real
    };
    // A byte has 256 values: each converted once (a power per channel of a large map was a
    // noticeable part of a short render's time).
    let table: [Real; 256] = std::array::from_fn(|c| linear(c as u8));
    let pixels = decoded
        .pixels()
        .map(|p| Vec3::new(table[p[0] as usize], table[p[1] as usize], table[p[2] as usize]))
        .collect();
    Ok(ImageTexture { width, height, pixels })
}

/// The planet raypool paints for the `next-week` scene (the book's earth, which the project
/// may not ship): an equirectangular map of Perlin continents, seas and ice caps.
pub fn planet() -> ImageTexture {
    let (width, height) = (512u32, 256u32);
    let noise = Perlin::new(0x706C_616E_6574);
    let pixels = (0..width * height)
        .map(|k| {
            let (i, j) = (k % width, k / width);
            let phi = (i as Real + 0.5) / width as Real * 2.0 * std::f64::consts::PI as Real;
            let theta = (j as Real + 0.5) / height as Real * std::f64::consts::PI as Real;
            let p = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()) * 2.5;
            let land = noise.noise(p) + 0.5 * noise.noise(2.0 * p) + 0.25 * noise.noise(4.0 * p);
            let latitude = theta.cos().abs();
            if latitude > 0.88 - 0.1 * land {
                Vec3::splat(0.85)
            } else if land > 0.05 {
                Vec3::new(0.18, 0.32, 0.08).lerp(Vec3::new(0.45, 0.36, 0.2), (land * 2.0).min(1.0))
            } else {
                Vec3::new(0.02, 0.06, 0.25).lerp(Vec3::new(0.05, 0.2, 0.45), (land + 0.5).clamp(0.0, 1.0))
            }
        })
        .collect();
    ImageTexture { width, height, pixels }
}
