//! Meshes: the embedded default head and OBJ files, with smooth normals.

use super::gpu_types::{SurfaceKind, Vertex};
use super::textures::MeshTextures;
use bytemuck::Zeroable;
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::path::Path;
use std::sync::Arc;

/// The default head (CC0 MakeHuman hm08, see assets/head/ATTRIBUTION.md),
/// subdivided once.
pub const DEFAULT_HEAD_OBJ: &str = include_str!("../../assets/head/head.obj");
/// The same head before subdivision: its coarse level of detail.
pub const DEFAULT_HEAD_BASE_OBJ: &str = include_str!("../../assets/head/head_base.obj");
/// Metres per unit of the default head (decimetres).
pub const DEFAULT_HEAD_METRES_PER_UNIT: f32 = 0.1;

/// Thickness where an inward ray leaves through an open boundary (mm).
pub const MAX_THICKNESS_MM: f32 = 100.0;

/// A triangle mesh ready for upload.
#[derive(Debug, Clone)]
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    pub metres_per_unit: f32,
    /// Where the camera looks (mesh units).
    pub focus: [f32; 3],
    /// Albedo, normal, roughness, mask and thickness maps (shared: the
    /// default head's bake is made once per process).
    pub textures: Arc<MeshTextures>,
    /// A coarser level of detail of the same surface and UV layout, drawn
    /// when this mesh's triangles would be only a few pixels on screen.
    pub coarse: Option<Box<Mesh>>,
}

/// A mesh's scale must be a positive, finite number of metres per unit.
fn check_scale(origin: &str, metres_per_unit: f32) -> Result<(), MeshError> {
    if metres_per_unit.is_finite() && metres_per_unit > 0.0 {
        Ok(())
    } else {
        Err(MeshError::Scale {
            path: origin.into(),
            value: metres_per_unit,
        })
    }
}

/// OBJ face indices count back from the elements read so far when
/// negative; tobj 4.0 turns one that reaches before the first element into
/// an overflowing multiplication (a panic in debug builds, a wrapped index
/// in release; found by fuzzing), and does the same with a positive index
/// so large that 3 × index overflows (found by fuzzing too). Refuse both
/// before tobj sees them: a relative index that reaches before the first
/// element read so far, and an absolute one beyond the file's count.
fn check_relative_indices(text: &str) -> Result<(), String> {
    const KINDS: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    let kind = |word: Option<&str>| match word {
        Some("v") => Some(0),
        Some("vt") => Some(1),
        Some("vn") => Some(2),
        _ => None,
    };
    let mut totals = [0i64; 3];
    for line in text.lines() {
        if let Some(k) = kind(line.split_whitespace().next()) {
            totals[k] += 1;
        }
    }
    let mut counts = [0i64; 3]; // v, vt, vn read so far
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let first = words.next();
        if let Some(k) = kind(first) {
            counts[k] += 1;
            continue;
        }
        if !matches!(first, Some("f") | Some("l") | Some("p")) {
            continue;
        }
        for corner in words {
            for (k, part) in corner.split('/').take(3).enumerate() {
                let Ok(i) = part.parse::<i64>() else { continue };
                if i < 0 && -i > counts[k] {
                    return Err(format!(
                        "line {}: index {i} reaches before the first {}",
                        n + 1,
                        KINDS[k]
                    ));
                }
                if i > totals[k] {
                    return Err(format!(
                        "line {}: index {i} is beyond the file's {} {}{}",
                        n + 1,
                        totals[k],
                        KINDS[k],
                        if totals[k] == 1 { "" } else { "s" }
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Largest accepted |coordinate| (mesh units): room for any real scan in
/// millimetres, far from f32's overflow when squared (3.4·10³⁸).
pub const MAX_COORDINATE: f32 = 1e9;

#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    #[error("{path}: cannot load mesh: {message}")]
    Load { path: String, message: String },
    #[error("{path}: the mesh has no triangles")]
    Empty { path: String },
    #[error("{path}: vertex {vertex} has a non-finite position {position:?}")]
    NonFinite {
        path: String,
        vertex: usize,
        position: [f32; 3],
    },
    #[error("{path}: vertex {vertex} lies at {position:?}, beyond ±{MAX_COORDINATE:e} units")]
    TooFar {
        path: String,
        vertex: usize,
        position: [f32; 3],
    },
    #[error("{path}: metres_per_unit = {value} must be finite and positive")]
    Scale { path: String, value: f32 },
    #[error("{path}: {part} has no texture coordinates (UVs); textures and tangents need them")]
    NoUvs { path: String, part: String },
    #[error("{path}: vertex {vertex} has a non-finite UV {uv:?}")]
    NonFiniteUv {
        path: String,
        vertex: usize,
        uv: [f32; 2],
    },
    #[error("{path}: every triangle's UVs have zero area; the mesh is not unwrapped")]
    ZeroAreaUvs { path: String },
    #[error(transparent)]
    Texture(#[from] super::textures::TextureError),
}

static DEFAULT_HEAD_MAPS: std::sync::OnceLock<Arc<MeshTextures>> = std::sync::OnceLock::new();

impl Mesh {
    /// The embedded head with its baked textures (baked once per process).
    pub fn default_head() -> Result<Self, MeshError> {
        let mut mesh = Self::default_head_without_maps()?;
        let maps = Self::default_head_maps(&mesh);
        mesh.set_maps(maps);
        Ok(mesh)
    }

    /// The embedded head, both levels of detail parsed and baked (normals,
    /// curvature, thickness) in parallel, with neutral surface maps: what
    /// the editor draws first while [`Mesh::default_head_maps`] bakes.
    pub fn default_head_without_maps() -> Result<Self, MeshError> {
        let (mesh, coarse) = rayon::join(
            || {
                Self::from_obj_text(
                    DEFAULT_HEAD_OBJ,
                    "<embedded default head>",
                    DEFAULT_HEAD_METRES_PER_UNIT,
                )
            },
            || {
                Self::from_obj_text(
                    DEFAULT_HEAD_BASE_OBJ,
                    "<embedded default head, coarse>",
                    DEFAULT_HEAD_METRES_PER_UNIT,
                )
            },
        );
        let (mut mesh, mut coarse) = (mesh?, coarse?);
        // One camera target for both levels.
        coarse.focus = mesh.focus;
        mesh.coarse = Some(Box::new(coarse));
        Ok(mesh)
    }

    /// The default head's surface maps (`procedural::bake`, about a second
    /// on two cores), baked on the first call in a process and shared
    /// after. `head` is [`Mesh::default_head_without_maps`].
    pub fn default_head_maps(head: &Mesh) -> Arc<MeshTextures> {
        DEFAULT_HEAD_MAPS
            .get_or_init(|| Arc::new(procedural::bake(head)))
            .clone()
    }

    /// Whether [`Mesh::default_head_maps`] has baked already.
    pub fn default_head_maps_baked() -> bool {
        DEFAULT_HEAD_MAPS.get().is_some()
    }

    /// Gives this mesh and its coarse level `maps`.
    pub fn set_maps(&mut self, maps: Arc<MeshTextures>) {
        if let Some(c) = &mut self.coarse {
            c.textures = maps.clone();
        }
        self.textures = maps;
    }

    /// The file extensions [`Mesh::load`] reads (lower case, no dot).
    pub const EXTENSIONS: [&'static str; 3] = ["obj", "gltf", "glb"];

    /// Loads an OBJ, glTF (.gltf) or binary glTF (.glb) file by extension.
    pub fn load(path: &Path, metres_per_unit: f32) -> Result<Self, MeshError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("gltf") | Some("glb") => gltf::load(path, metres_per_unit),
            _ => Self::load_obj(path, metres_per_unit),
        }
    }

    pub fn load_obj(path: &Path, metres_per_unit: f32) -> Result<Self, MeshError> {
        let load_error = |message: String| MeshError::Load {
            path: path.display().to_string(),
            message,
        };
        let len = crate::fsutil::file_len(path).map_err(|e| load_error(e.to_string()))?;
        if let Some(problem) = crate::fsutil::too_short(len, 1, "an OBJ mesh") {
            return Err(load_error(problem));
        }
        let text = std::fs::read_to_string(path).map_err(|e| load_error(e.to_string()))?;
        Self::from_obj_text(&text, &path.display().to_string(), metres_per_unit)
    }

    /// Parses OBJ text; groups named `eyes`/`teeth` become non-scattering
    /// materials. OBJ's v runs up the image; it is flipped to the top-left
    /// origin the renderer (and glTF) use.
    pub fn from_obj_text(
        text: &str,
        origin: &str,
        metres_per_unit: f32,
    ) -> Result<Self, MeshError> {
        check_scale(origin, metres_per_unit)?;
        check_relative_indices(text).map_err(|message| MeshError::Load {
            path: origin.into(),
            message,
        })?;
        let mut reader = std::io::BufReader::new(text.as_bytes());
        let opts = tobj::LoadOptions {
            triangulate: true,
            single_index: true,
            ..Default::default()
        };
        let (models, _) =
            tobj::load_obj_buf(&mut reader, &opts, |_| Ok((Vec::new(), Default::default())))
                .map_err(|e| MeshError::Load {
                    path: origin.into(),
                    message: e.to_string(),
                })?;
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        for m in &models {
            let material = match m.name.as_str() {
                "eyes" => SurfaceKind::Eye,
                "teeth" => SurfaceKind::Teeth,
                _ => SurfaceKind::Skin,
            }
            .code();
            let base = vertices.len() as u32;
            let p = &m.mesh.positions;
            let t = &m.mesh.texcoords;
            if t.len() < 2 * (p.len() / 3) && !m.mesh.indices.is_empty() {
                return Err(MeshError::NoUvs {
                    path: origin.into(),
                    part: format!("group '{}'", m.name),
                });
            }
            for i in 0..p.len() / 3 {
                vertices.push(Vertex {
                    position: [p[3 * i], p[3 * i + 1], p[3 * i + 2]],
                    uv: [t[2 * i], 1.0 - t[2 * i + 1]],
                    material,
                    ..Vertex::zeroed()
                });
            }
            indices.extend(m.mesh.indices.iter().map(|i| base + i));
        }
        Self::from_triangles(vertices, indices, origin, metres_per_unit, false)
    }

    /// Validates and prepares triangles from any loader: positions finite,
    /// UVs with area, smooth normals (unless `has_normals`), tangents,
    /// curvature and the thickness bake, and the camera's focus.
    pub(super) fn from_triangles(
        vertices: Vec<Vertex>,
        indices: Vec<u32>,
        origin: &str,
        metres_per_unit: f32,
        has_normals: bool,
    ) -> Result<Self, MeshError> {
        check_scale(origin, metres_per_unit)?;
        let mut mesh = Mesh {
            vertices,
            indices,
            metres_per_unit,
            focus: [0.0; 3],
            textures: Arc::new(MeshTextures::default()),
            coarse: None,
        };
        if mesh.indices.is_empty() {
            return Err(MeshError::Empty {
                path: origin.into(),
            });
        }
        // A NaN or Inf position would poison the normals, bounds and bakes.
        if let Some((vertex, v)) = mesh
            .vertices
            .iter()
            .enumerate()
            .find(|(_, v)| !v.position.iter().all(|x| x.is_finite()))
        {
            return Err(MeshError::NonFinite {
                path: origin.into(),
                vertex: vertex + 1,
                position: v.position,
            });
        }
        // So would a finite one whose squared extent overflows f32 (the
        // thickness bake then marched forever; found by fuzzing).
        if let Some((vertex, v)) = mesh
            .vertices
            .iter()
            .enumerate()
            .find(|(_, v)| v.position.iter().any(|x| x.abs() > MAX_COORDINATE))
        {
            return Err(MeshError::TooFar {
                path: origin.into(),
                vertex: vertex + 1,
                position: v.position,
            });
        }
        if let Some((vertex, v)) = mesh
            .vertices
            .iter()
            .enumerate()
            .find(|(_, v)| !v.uv.iter().all(|x| x.is_finite()))
        {
            return Err(MeshError::NonFiniteUv {
                path: origin.into(),
                vertex: vertex + 1,
                uv: v.uv,
            });
        }
        let uv_area: f64 = mesh
            .indices
            .chunks_exact(3)
            .map(|t| {
                let uv = |i: u32| Vec2::from(mesh.vertices[i as usize].uv);
                ((uv(t[1]) - uv(t[0])).perp_dot(uv(t[2]) - uv(t[0])) as f64).abs()
            })
            .sum();
        if !(uv_area > 1e-12) {
            return Err(MeshError::ZeroAreaUvs {
                path: origin.into(),
            });
        }
        // A file's normals are kept unless any is missing or degenerate.
        let usable = |n: &[f32; 3]| {
            let n = Vec3::from(*n);
            n.is_finite() && n.length_squared() > 1e-12
        };
        if !has_normals || !mesh.vertices.iter().all(|v| usable(&v.normal)) {
            mesh.compute_smooth_normals();
        }
        if mesh.vertices.iter().any(|v| v.tangent == [0.0; 4]) {
            mesh.compute_tangents();
        }
        mesh.compute_curvature(2);
        mesh.bake_thickness(MAX_THICKNESS_MM);
        // Look at eye height: 62 % up the bounding box (the face of a head).
        let (lo, hi) = mesh.bounds();
        mesh.focus = [
            0.5 * (lo.x + hi.x),
            lo.y + 0.62 * (hi.y - lo.y),
            0.5 * (lo.z + hi.z),
        ];
        Ok(mesh)
    }

    /// A square of side `size` (units) in the z = 0 plane facing +z, all skin.
    pub fn plane(size: f32, metres_per_unit: f32) -> Self {
        let h = 0.5 * size;
        let v = |x: f32, y: f32, u: f32, w: f32| Vertex {
            position: [x, y, 0.0],
            normal: [0.0, 0.0, 1.0],
            uv: [u, w],
            material: 0.0,
            curvature_per_mm: 0.0,
            thickness_mm: 1.0,
            tangent: [1.0, 0.0, 0.0, 1.0],
        };
        Mesh {
            vertices: vec![
                v(-h, -h, 0.0, 1.0),
                v(h, -h, 1.0, 1.0),
                v(h, h, 1.0, 0.0),
                v(-h, h, 0.0, 0.0),
            ],
            indices: vec![0, 1, 2, 0, 2, 3],
            metres_per_unit,
            focus: [0.0; 3],
            textures: Arc::new(MeshTextures::default()),
            coarse: None,
        }
    }

    /// Mean edge length (mesh units): the renderer's level-of-detail measure.
    pub fn mean_edge(&self) -> f32 {
        let mut sum = 0.0f64;
        for tri in self.indices.chunks_exact(3) {
            for k in 0..3 {
                let a = Vec3::from(self.vertices[tri[k] as usize].position);
                let b = Vec3::from(self.vertices[tri[(k + 1) % 3] as usize].position);
                sum += (b - a).length() as f64;
            }
        }
        (sum / self.indices.len().max(1) as f64) as f32
    }

    /// The eyeballs: the vertices of material 1 (an OBJ group `eyes`),
    /// split into left and right by x about their mean, each taken as a
    /// sphere with its bounding box's centre and half its largest extent
    /// (mesh units); `[centre, radius]`, radius 0 where there is none.
    pub fn eyeballs(&self) -> [[f32; 4]; 2] {
        let eye: Vec<Vec3> = self
            .vertices
            .iter()
            .filter(|v| SurfaceKind::of(v.material) == SurfaceKind::Eye)
            .map(|v| Vec3::from(v.position))
            .collect();
        let mut out = [[0.0; 4]; 2];
        if eye.is_empty() {
            return out;
        }
        let mid = eye.iter().map(|p| p.x).sum::<f32>() / eye.len() as f32;
        for (k, right) in [false, true].into_iter().enumerate() {
            let side = eye.iter().filter(|p| (p.x > mid) == right);
            let (lo, hi) = side.fold(
                (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            if lo.x <= hi.x {
                let c = 0.5 * (lo + hi);
                out[k] = [c.x, c.y, c.z, 0.5 * (hi - lo).max_element()];
            }
        }
        out
    }

    /// Height of the bounding box in metres (y up, as OBJ and glTF are).
    pub fn height_m(&self) -> f32 {
        let (lo, hi) = self.bounds();
        (hi.y - lo.y).max(0.0) * self.metres_per_unit
    }

    /// Camera distance (m) that frames the mesh: its bounding-box height
    /// fills the vertical field of view at the focus (for the default
    /// head, 0.308 m tall at 30°, 0.574 m; its fixed 0.55 m cropped it).
    pub fn framing_distance_m(&self, fov_y: f32) -> f32 {
        framing_distance_m(self.height_m(), fov_y)
    }

    /// A sphere that holds every vertex, in metres: its centre (the
    /// bounding box's) from the focus, and its radius (the farthest vertex
    /// from that centre). What the editor's F frames whole.
    pub fn bounds_sphere_m(&self) -> ([f32; 3], f32) {
        let (lo, hi) = self.bounds();
        if lo.x > hi.x {
            return ([0.0; 3], 0.0);
        }
        let c = 0.5 * (lo + hi);
        let r = self
            .vertices
            .iter()
            .map(|v| Vec3::from(v.position).distance(c))
            .fold(0.0f32, f32::max);
        let m = self.metres_per_unit;
        (((c - Vec3::from(self.focus)) * m).to_array(), r * m)
    }

    /// Axis-aligned bounds (min, max) in mesh units.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.vertices.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), v| {
                let p = Vec3::from(v.position);
                (lo.min(p), hi.max(p))
            },
        )
    }
}

mod geometry;
/// The mesh written as an OBJ in metres.
mod obj_out;
/// Which way a mesh faces, and a file inside out turned outward.
mod orientation;
pub use orientation::Facing;
/// glTF 2.0 meshes (.gltf/.glb) with their buffers and textures.
mod gltf;
/// The default head's UV-space bake (its procedural maps).
pub mod procedural;

#[cfg(test)]
mod tests;

/// The thickness bake's progress in this process: vertices done and in
/// all, of the bake running now or last (for the editor's progress bar; a
/// load on another thread of the same process would share it).
pub static BAKE_PROGRESS: [std::sync::atomic::AtomicU32; 2] = [
    std::sync::atomic::AtomicU32::new(0),
    std::sync::atomic::AtomicU32::new(0),
];

/// Fraction of the current thickness bake done, in [0, 1].
pub fn bake_fraction() -> f32 {
    use std::sync::atomic::Ordering;
    let total = BAKE_PROGRESS[1].load(Ordering::Relaxed);
    if total == 0 {
        return 0.0;
    }
    (BAKE_PROGRESS[0].load(Ordering::Relaxed) as f32 / total as f32).min(1.0)
}

/// Distance (m) at which an object `height_m` tall fills a vertical field
/// of view `fov_y` (radians): h/2 = d·tan(fov/2).
pub fn framing_distance_m(height_m: f32, fov_y: f32) -> f32 {
    let h = if height_m.is_finite() && height_m > 0.0 {
        height_m
    } else {
        0.3
    };
    0.5 * h / (0.5 * fov_y).tan()
}

/// Plausible height of a head-and-shoulders or a bust in metres: outside
/// it a mesh's units are probably not what `metres_per_unit` says.
pub const PLAUSIBLE_HEIGHT_M: (f32, f32) = (0.1, 1.0);

/// The cranium's size (m) that [`HeadSize::cranium_units`] measures: the
/// mean of its greatest width (ears included) and depth (nose included).
/// Taken from MakeHuman's hm08 base mesh, an average adult modelled in
/// decimetres (our default head): 17.5 cm wide and 19.7 cm deep, mean
/// 18.6 cm (`head_size_of_the_default_head_and_a_scan`).
pub const CRANIUM_M: f32 = 0.186;

/// Cranium sizes (m) an adult or a child head can have; outside them the
/// units are probably wrong. Heads vary by about ±10 % about
/// [`CRANIUM_M`]; the range leaves room for stylised characters.
pub const PLAUSIBLE_CRANIUM_M: (f32, f32) = (0.13, 0.3);

/// A mesh's size in its own units, for judging the units it was saved in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeadSize {
    /// Bounding-box height (y up, as OBJ and glTF are).
    pub height_units: f32,
    /// Mean of the width (x) and depth (z) of the head's top part, from the
    /// crown down to the neck; `None` when the mesh has no such part (a
    /// flat card, a face mask, a box). Unlike the height, it does not
    /// depend on how much neck, shoulder or body the file includes.
    pub cranium_units: Option<f32>,
}

impl HeadSize {
    /// Measures `positions` (mesh units, y up). The mesh is cut into 20
    /// horizontal slices; walking down from the crown, the cranium ends at
    /// the first slice narrower (in x) than 3/4 of the widest slice above
    /// it: the neck. A head is about as deep as it is wide, so a cranium
    /// whose depth and width differ by more than 2× is not one.
    pub fn measure(positions: impl Iterator<Item = Vec3> + Clone) -> Self {
        const SLICES: usize = 20;
        let (lo, hi) = positions.clone().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(p), hi.max(p)),
        );
        let height_units = (hi.y - lo.y).max(0.0);
        let mut size = Self {
            height_units,
            cranium_units: None,
        };
        if !(height_units.is_finite() && height_units > 0.0) {
            return size;
        }
        // Per slice from the top: (min, max) of x and of z.
        let mut slices = [(Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)); SLICES];
        for p in positions {
            let k = (((hi.y - p.y) / height_units) * SLICES as f32) as usize;
            let s = &mut slices[k.min(SLICES - 1)];
            *s = (s.0.min(p), s.1.max(p));
        }
        let (mut widest, mut width, mut depth, mut filled) = (0f32, 0f32, 0f32, 0);
        for (lo, hi) in slices.iter().filter(|(lo, hi)| lo.x <= hi.x) {
            let w = hi.x - lo.x;
            if filled > 0 && w < 0.75 * widest {
                break;
            }
            widest = widest.max(w);
            width = width.max(w);
            depth = depth.max(hi.z - lo.z);
            filled += 1;
        }
        if filled >= 3 && width > 0.0 && depth > 0.0 && (0.5..=2.0).contains(&(depth / width)) {
            size.cranium_units = Some(0.5 * (width + depth));
        }
        size
    }

    /// The metres per unit to suggest: the one that makes the cranium
    /// [`CRANIUM_M`] (else the whole mesh 25 cm tall), replaced by a
    /// common unit (m, dm, cm, mm, inch) that lies within −20 %/+20 % of it
    /// (−28 %/+60 % from the height: 18–40 cm, a head with or without
    /// neck and shoulders), else rounded to three significant digits, and
    /// kept within what a mesh load accepts (1e-6–1e3).
    pub fn suggest_metres_per_unit(&self) -> f32 {
        let (x, lo, hi) = match self.cranium_units {
            Some(c) => (CRANIUM_M / c, 0.8, 1.2),
            None => (0.25 / self.height_units.max(1e-9), 0.72, 1.6),
        };
        if !x.is_finite() {
            return 1e3;
        }
        for v in [1.0, 0.1, 0.01, 0.001, 0.0254] {
            if (lo * x..=hi * x).contains(&v) {
                return v;
            }
        }
        let mag = 10f32.powf(x.log10().floor() - 2.0);
        ((x / mag).round() * mag).clamp(1e-6, 1e3)
    }

    /// A one-line warning when the size implied by `metres_per_unit` is
    /// implausible for a head (the cranium outside
    /// [`PLAUSIBLE_CRANIUM_M`], else the height outside
    /// [`PLAUSIBLE_HEIGHT_M`]), naming [`Self::suggest_metres_per_unit`].
    pub fn scale_warning(&self, metres_per_unit: f32) -> Option<String> {
        let fix = self.suggest_metres_per_unit();
        let h = self.height_units * metres_per_unit;
        match self.cranium_units.map(|c| c * metres_per_unit) {
            Some(c) if !(c.is_finite() && c > 0.0) => None,
            Some(c) if (PLAUSIBLE_CRANIUM_M.0..=PLAUSIBLE_CRANIUM_M.1).contains(&c) => None,
            Some(c) => Some(format!(
                "the head is {:.1} cm across at {metres_per_unit} m/unit ({h:.3} m tall), an adult's about {:.0}: its units may differ (--metres-per-unit {fix} would make it {:.1} cm)",
                100.0 * c,
                100.0 * CRANIUM_M,
                100.0 * self.cranium_units.unwrap_or(0.0) * fix,
            )),
            None if !(h.is_finite() && h > 0.0)
                || (PLAUSIBLE_HEIGHT_M.0..=PLAUSIBLE_HEIGHT_M.1).contains(&h) =>
            {
                None
            }
            None => Some(format!(
                "the mesh is {h:.3} m tall at {metres_per_unit} m/unit, not a head's 0.1–1 m: its units may differ (--metres-per-unit {fix} would make it {:.2} m)",
                self.height_units * fix
            )),
        }
    }
}

impl Mesh {
    /// [`HeadSize::measure`] of this mesh's vertices.
    pub fn head_size(&self) -> HeadSize {
        HeadSize::measure(self.vertices.iter().map(|v| Vec3::from(v.position)))
    }
}

#[cfg(test)]
mod framing_tests;
