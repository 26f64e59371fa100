//! `.rayvis` files: RayVis's ray data in an RDF container (`rdf`): one `RAYVIS_SCENE` chunk and
//! one `RAYVIS_RAYTRACE` chunk per trace, laid out as seed 002's listings A.1 and A.2. The
//! listings leave sizes and padding open; Voxcast pins them as follows (little endian, `size_t`
//! is u64, natural MSVC x64 alignment):
//!
//! * `RAYVIS_RAYTRACE`: header `u32 traceId`; data, one 52-byte record per ray: `u32 rayId`,
//!   `f32×3 origin`, `f32 tMin`, `f32×3 direction`, `f32 tMax`, `f32 tHit`, `u32×3 hitInfo`.
//! * `RAYVIS_SCENE`: header `u64 meshCount, u64 rootNodeCount`; data, the meshes — per mesh
//!   `u64 primitiveCount`, per primitive `u64 vertexByteSize` (one vertex's bytes, at least 12:
//!   the position is its first `f32×3`), `u64 vertexCount`, `u64 indexByteSize` (2 or 4),
//!   `u64 indexCount`, the vertices, the indices (triangles, three a triangle) — then per root
//!   node `u64 nodeCount, u64 rootNodeId` (0) and its nodes, each a 104-byte record
//!   (`u64 childCount`, `u64 meshId` (u64::MAX: none), `f32×3 meshColor`, `i32 id`,
//!   `u8 instanceMask`, 3 padding bytes, `f32×16` matrix row-major, 4 padding bytes) followed
//!   by its `childCount` u32 child ids.
//!
//! A node's matrix places it in its parent's space: row-major, acting on column vectors
//! (translation in the last column), as the listing's DirectX-style renderer stores it
//! transposed; a matrix whose last column is (0, 0, 0, 1) and last row is not is read the other
//! way round. A node's place in the world is its matrix composed down the tree from its
//! group's root (`rootNodeId`) through every parent; a node no parent names is placed from its
//! own matrix, as a root, and a cycle (a node reached twice) is an error.

use super::data::RayData;
use super::mesh::{Mesh, TriangleScene};
use super::rdf::{self, Chunk, RdfError};
use super::set::{RayRecord, RaySet};
use glam::{Mat4, Vec3, Vec4};

/// The chunk identifiers.
pub const SCENE_CHUNK: &str = "RAYVIS_SCENE";
pub const TRACE_CHUNK: &str = "RAYVIS_RAYTRACE";
/// Bytes of one ray record.
pub const RAY_BYTES: usize = 52;
const NODE_BYTES: usize = 104;

/// Reads the bytes of a `.rayvis` file.
pub fn read(file: &[u8], name: &str) -> Result<RayData, RdfError> {
    let chunks = rdf::read(file)?;
    let mut scene = TriangleScene::default();
    let mut scenes = 0;
    let mut traces = Vec::new();
    for c in &chunks {
        match c.id.as_str() {
            SCENE_CHUNK => {
                scenes += 1;
                scene.meshes.extend(read_scene(c)?.meshes);
            }
            TRACE_CHUNK => traces.push(read_trace(c)?),
            _ => {} // other chunks (a renderer's own) are passed over
        }
    }
    if traces.is_empty() {
        return Err(RdfError::Bad(format!(
            "{name} holds no {TRACE_CHUNK} chunk: no rays"
        )));
    }
    Ok(RayData {
        description: format!(
            "a RayVis file: {} trace{}, {} scene chunk{}",
            traces.len(),
            if traces.len() == 1 { "" } else { "s" },
            scenes,
            if scenes == 1 { "" } else { "s" }
        ),
        scene,
        traces,
    })
}

/// A cursor over a chunk's bytes that names what it was reading when they ran out.
struct Cursor<'b> {
    bytes: &'b [u8],
    at: usize,
    chunk: &'static str,
}

impl<'b> Cursor<'b> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'b [u8], RdfError> {
        match self.at.checked_add(n) {
            Some(end) if end <= self.bytes.len() => {
                let s = &self.bytes[self.at..end];
                self.at = end;
                Ok(s)
            }
            _ => Err(RdfError::Truncated(format!(
                "{}'s {what} (byte {} of {})",
                self.chunk,
                self.at,
                self.bytes.len()
            ))),
        }
    }
    fn u64(&mut self, what: &str) -> Result<u64, RdfError> {
        Ok(u64::from_le_bytes(
            self.take(8, what)?.try_into().expect("8"),
        ))
    }
    fn u32(&mut self, what: &str) -> Result<u32, RdfError> {
        Ok(u32::from_le_bytes(
            self.take(4, what)?.try_into().expect("4"),
        ))
    }
    fn f32(&mut self, what: &str) -> Result<f32, RdfError> {
        Ok(f32::from_le_bytes(
            self.take(4, what)?.try_into().expect("4"),
        ))
    }
    fn vec3(&mut self, what: &str) -> Result<Vec3, RdfError> {
        Ok(Vec3::new(self.f32(what)?, self.f32(what)?, self.f32(what)?))
    }
    /// `count` items of `each` bytes, all of them within the bytes left.
    fn array(&mut self, count: u64, each: u64, what: &str) -> Result<&'b [u8], RdfError> {
        let left = (self.bytes.len() - self.at) as u64;
        let n = count
            .checked_mul(each)
            .filter(|&n| n <= left)
            .ok_or_else(|| RdfError::Truncated(format!("{}'s {count} {what}", self.chunk)))?;
        self.take(n as usize, what)
    }

    /// A count of items of at least `min_bytes` each: no more than the bytes left can hold.
    fn count(&mut self, min_bytes: usize, what: &str) -> Result<usize, RdfError> {
        let n = self.u64(what)?;
        let left = (self.bytes.len() - self.at) as u64;
        if n > left / min_bytes.max(1) as u64 {
            return Err(RdfError::Bad(format!(
                "{}'s {what} is {n}, more than its {left} remaining bytes can hold",
                self.chunk
            )));
        }
        Ok(n as usize)
    }
}

fn read_trace(c: &Chunk) -> Result<RaySet, RdfError> {
    let mut h = Cursor {
        bytes: &c.header,
        at: 0,
        chunk: TRACE_CHUNK,
    };
    let trace_id = h.u32("header (traceId)")?;
    if !c.data.len().is_multiple_of(RAY_BYTES) {
        return Err(RdfError::Bad(format!(
            "{TRACE_CHUNK} {trace_id}: {} bytes of rays are not a whole number of {RAY_BYTES}-byte records",
            c.data.len()
        )));
    }
    let mut d = Cursor {
        bytes: &c.data,
        at: 0,
        chunk: TRACE_CHUNK,
    };
    let mut rays = Vec::with_capacity(c.data.len() / RAY_BYTES);
    for _ in 0..c.data.len() / RAY_BYTES {
        let id = d.u32("ray")?;
        let origin = d.vec3("ray")?;
        let t_min = d.f32("ray")?;
        let direction = d.vec3("ray")?;
        let t_max = d.f32("ray")?;
        let t_hit = d.f32("ray")?;
        d.take(12, "ray")?; // hitInfo: the renderer's own
        rays.push(RayRecord {
            id,
            origin,
            direction,
            t_min,
            t_max,
            t_hit,
        });
    }
    Ok(RaySet { trace_id, rays })
}

/// The 4×4 matrix stored row-major, as it acts on column vectors.
fn node_matrix(m: [f32; 16]) -> Mat4 {
    let rows = Mat4::from_cols_array(&m).transpose();
    let last_row = rows.row(3);
    let last_col = rows.col(3);
    if last_row != Vec4::W && last_col == Vec4::W {
        rows.transpose()
    } else {
        rows
    }
}

fn read_scene(c: &Chunk) -> Result<TriangleScene, RdfError> {
    let mut h = Cursor {
        bytes: &c.header,
        at: 0,
        chunk: SCENE_CHUNK,
    };
    let mesh_count = h.u64("header (meshCount)")?;
    let root_count = h.u64("header (rootNodeCount)")?;
    let mut d = Cursor {
        bytes: &c.data,
        at: 0,
        chunk: SCENE_CHUNK,
    };
    // Meshes: triangles in the mesh's own space.
    let mut meshes: Vec<Vec<[Vec3; 3]>> = Vec::new();
    for m in 0..mesh_count {
        if m > c.data.len() as u64 / 8 {
            return Err(RdfError::Bad(format!(
                "{SCENE_CHUNK}'s meshCount {mesh_count} is more than its data can hold"
            )));
        }
        let primitives = d.count(32, "primitiveCount")?;
        let mut triangles = Vec::new();
        for _ in 0..primitives {
            let vertex_bytes = d.u64("vertexByteSize")?;
            if !(12..=1024).contains(&vertex_bytes) {
                return Err(RdfError::Bad(format!(
                    "{SCENE_CHUNK}: a vertex of {vertex_bytes} bytes (at least 12: f32×3)"
                )));
            }
            let vertex_count = d.u64("vertexCount")?;
            let index_bytes = d.u64("indexByteSize")?;
            if index_bytes != 2 && index_bytes != 4 {
                return Err(RdfError::Bad(format!(
                    "{SCENE_CHUNK}: indices of {index_bytes} bytes (2 or 4)"
                )));
            }
            let index_count = d.u64("indexCount")?;
            let raw = d.array(vertex_count, vertex_bytes, "vertices")?;
            let vertices: Vec<Vec3> = raw
                .chunks_exact(vertex_bytes as usize)
                .map(|v| {
                    let f =
                        |i: usize| f32::from_le_bytes(v[i * 4..i * 4 + 4].try_into().expect("4"));
                    Vec3::new(f(0), f(1), f(2))
                })
                .collect();
            let raw = d.array(index_count, index_bytes, "indices")?;
            let indices: Vec<usize> = raw
                .chunks_exact(index_bytes as usize)
                .map(|b| match b.len() {
                    2 => u16::from_le_bytes([b[0], b[1]]) as usize,
                    _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
                })
                .collect();
            for tri in indices.chunks_exact(3) {
                let corner = |i: usize| {
                    vertices.get(i).copied().ok_or_else(|| {
                        RdfError::Bad(format!(
                            "{SCENE_CHUNK}: index {i} past the primitive's {} vertices",
                            vertices.len()
                        ))
                    })
                };
                triangles.push([corner(tri[0])?, corner(tri[1])?, corner(tri[2])?]);
            }
        }
        meshes.push(triangles);
    }
    // Nodes: each group read whole, then placed down its tree.
    let mut scene = TriangleScene::default();
    for _ in 0..root_count {
        let count = d.count(NODE_BYTES, "nodeCount")?;
        let root_id = d.u64("rootNodeId")?;
        let mut nodes = Vec::with_capacity(count);
        for _ in 0..count {
            nodes.push(read_node(&mut d, meshes.len())?);
        }
        place_nodes(&nodes, root_id, &meshes, &mut scene)?;
    }
    Ok(scene)
}

/// One node as stored: its id, mesh, colour, matrix (in its parent's space) and children.
struct Node {
    id: i32,
    mesh: Option<usize>,
    color: Vec3,
    local: Mat4,
    children: Vec<u32>,
}

fn read_node(d: &mut Cursor<'_>, mesh_count: usize) -> Result<Node, RdfError> {
    let children = d.u64("childCount")?;
    let mesh_id = d.u64("meshId")?;
    let color = d.vec3("meshColor")?;
    let id = d.u32("id")? as i32;
    d.take(4, "instanceMask and padding")?;
    let mut m = [0f32; 16];
    for v in &mut m {
        *v = d.f32("matrix")?;
    }
    d.take(4, "padding")?;
    if children > ((d.bytes.len() - d.at) / 4) as u64 {
        return Err(RdfError::Bad(format!(
            "{SCENE_CHUNK}: node {id} has {children} children, more than the data holds"
        )));
    }
    let mut ids = Vec::with_capacity(children as usize);
    for _ in 0..children {
        ids.push(d.u32("child id")?);
    }
    let mesh = match mesh_id {
        u64::MAX => None,
        m if (m as usize) < mesh_count => Some(m as usize),
        m => {
            return Err(RdfError::Bad(format!(
                "{SCENE_CHUNK}: node {id} names mesh {m} of {mesh_count}"
            )));
        }
    };
    Ok(Node {
        id,
        mesh,
        color,
        local: node_matrix(m),
        children: ids,
    })
}

/// Places one group's nodes: from the root down, each node's world matrix its parent's times
/// its own; then, the same way, from each node no node names as a child. A node reached twice,
/// or never (a cycle), is an error.
fn place_nodes(
    nodes: &[Node],
    root_id: u64,
    meshes: &[Vec<[Vec3; 3]>],
    scene: &mut TriangleScene,
) -> Result<(), RdfError> {
    let index_of = |id: i64| nodes.iter().position(|n| i64::from(n.id) == id);
    let mut placed = vec![false; nodes.len()];
    let named: std::collections::HashSet<u32> = nodes
        .iter()
        .flat_map(|n| n.children.iter().copied())
        .collect();
    let orphans = (0..nodes.len()).filter(|&i| !named.contains(&(nodes[i].id as u32)));
    let roots: Vec<usize> = index_of(root_id as i64)
        .into_iter()
        .chain(orphans)
        .collect();
    for root in roots {
        if placed[root] {
            continue;
        }
        let mut stack = vec![(root, Mat4::IDENTITY)];
        while let Some((i, parent)) = stack.pop() {
            if std::mem::replace(&mut placed[i], true) {
                return Err(RdfError::Bad(format!(
                    "{SCENE_CHUNK}: node {} is reached twice (a cycle or a shared child)",
                    nodes[i].id
                )));
            }
            let n = &nodes[i];
            let to_world = parent * n.local;
            if let Some(m) = n.mesh {
                scene.meshes.push(Mesh {
                    name: format!("node {} (mesh {m})", n.id),
                    color: n.color,
                    triangles: meshes[m]
                        .iter()
                        .map(|t| t.map(|p| to_world.transform_point3(p)))
                        .collect(),
                });
            }
            for &child in n.children.iter().rev() {
                let Some(c) = index_of(i64::from(child)) else {
                    return Err(RdfError::Bad(format!(
                        "{SCENE_CHUNK}: node {} names child {child}, which is not in its group",
                        n.id
                    )));
                };
                stack.push((c, to_world));
            }
        }
    }
    match placed.iter().position(|p| !p) {
        Some(i) => Err(RdfError::Bad(format!(
            "{SCENE_CHUNK}: node {} is in a cycle no root reaches",
            nodes[i].id
        ))),
        None => Ok(()),
    }
}

/// `data` as a `.rayvis` file: its scene (a mesh and a node per mesh, placed by the identity)
/// and its traces.
pub fn write(data: &RayData) -> Vec<u8> {
    let mut chunks = Vec::new();
    let mut header = Vec::new();
    header.extend_from_slice(&(data.scene.meshes.len() as u64).to_le_bytes());
    header.extend_from_slice(&1u64.to_le_bytes());
    let mut body = Vec::new();
    let put64 = |b: &mut Vec<u8>, v: u64| b.extend_from_slice(&v.to_le_bytes());
    for m in &data.scene.meshes {
        put64(&mut body, 1);
        let n = m.triangles.len() as u64 * 3;
        for v in [12, n, 4, n] {
            put64(&mut body, v);
        }
        for p in m.triangles.iter().flatten() {
            for c in p.to_array() {
                body.extend_from_slice(&c.to_le_bytes());
            }
        }
        for i in 0..n as u32 {
            body.extend_from_slice(&i.to_le_bytes());
        }
    }
    put64(&mut body, data.scene.meshes.len() as u64);
    put64(&mut body, 0);
    for (i, m) in data.scene.meshes.iter().enumerate() {
        put64(&mut body, 0); // childCount
        put64(&mut body, i as u64);
        for c in m.color.to_array() {
            body.extend_from_slice(&c.to_le_bytes());
        }
        body.extend_from_slice(&(i as i32).to_le_bytes());
        body.extend_from_slice(&[0xff, 0, 0, 0]);
        for c in Mat4::IDENTITY.transpose().to_cols_array() {
            body.extend_from_slice(&c.to_le_bytes());
        }
        body.extend_from_slice(&[0; 4]);
    }
    chunks.push(Chunk {
        id: SCENE_CHUNK.into(),
        version: 1,
        header,
        data: body,
    });
    for t in &data.traces {
        let mut rays = Vec::with_capacity(t.rays.len() * RAY_BYTES);
        for r in &t.rays {
            rays.extend_from_slice(&r.id.to_le_bytes());
            for f in [
                r.origin.x,
                r.origin.y,
                r.origin.z,
                r.t_min,
                r.direction.x,
                r.direction.y,
                r.direction.z,
                r.t_max,
                r.t_hit,
            ] {
                rays.extend_from_slice(&f.to_le_bytes());
            }
            rays.extend_from_slice(&[0; 12]);
        }
        chunks.push(Chunk {
            id: TRACE_CHUNK.into(),
            version: 1,
            header: t.trace_id.to_le_bytes().to_vec(),
            data: rays,
        });
    }
    rdf::write(&chunks)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> RayData {
        let mut d = super::super::source::load("builtin:cornell").unwrap();
        for t in &mut d.traces {
            t.rays.truncate(500);
        }
        d
    }

    #[test]
    fn the_cornell_box_round_trips_through_a_rayvis_file() {
        let d = small();
        let file = write(&d);
        let back = read(&file, "cornell.rayvis").unwrap();
        assert_eq!(back.traces, d.traces);
        assert_eq!(back.scene.meshes.len(), d.scene.meshes.len());
        for (a, b) in back.scene.meshes.iter().zip(&d.scene.meshes) {
            assert_eq!(a.triangles, b.triangles);
            assert_eq!(a.color, b.color);
        }
        // The records have the pinned sizes: 52 bytes a ray.
        let chunks = rdf::read(&file).unwrap();
        assert_eq!(chunks[1].data.len(), 500 * RAY_BYTES);
    }

    /// A hierarchy two levels deep, written by an independent writer
    /// (`tests/data/two_level_rayvis.py`, from the listings and the RDF specification): each
    /// mesh placed by its matrices composed from the root down.
    #[test]
    fn a_node_hierarchy_is_composed_from_the_root_down() {
        let bytes = include_bytes!("../../../../tests/data/two_level.rayvis");
        let d = read(bytes, "two_level.rayvis").unwrap();
        let placed: Vec<[Vec3; 3]> = d.scene.meshes.iter().map(|m| m.triangles[0]).collect();
        let v = Vec3::new;
        let want = [
            [v(10.0, 5.0, 0.0), v(12.0, 5.0, 0.0), v(10.0, 7.0, 0.0)],
            [v(10.0, 5.0, 6.0), v(10.0, 7.0, 6.0), v(8.0, 5.0, 6.0)],
        ];
        assert_eq!(placed.len(), 2, "the root has no mesh");
        for (got, want) in placed.iter().zip(&want) {
            for (a, b) in got.iter().zip(want) {
                assert!(a.abs_diff_eq(*b, 1e-5), "{got:?} vs {want:?}");
            }
        }
        assert_eq!(d.traces[0].trace_id, 7);
        assert_eq!(d.traces[0].rays[0].origin, v(0.0, 0.0, -5.0));
        // The same with the grandchild naming its parent as a child: an error, not a loop.
        let cycle = include_bytes!("../../../../tests/data/cycle.rayvis");
        let e = read(cycle, "cycle.rayvis").unwrap_err().to_string();
        assert!(e.contains("node 1 is reached twice"), "{e}");
    }

    #[test]
    fn a_node_matrix_places_its_mesh_in_either_storage_order() {
        let t = Mat4::from_translation(Vec3::new(10.0, 20.0, 30.0));
        // Row-major acting on column vectors: the translation in the last column.
        let row_major = t.transpose().to_cols_array();
        let p = node_matrix(row_major).transform_point3(Vec3::ONE);
        assert_eq!(p, Vec3::new(11.0, 21.0, 31.0));
        // Stored the other way (translation in the last row).
        let p = node_matrix(t.to_cols_array()).transform_point3(Vec3::ONE);
        assert_eq!(p, Vec3::new(11.0, 21.0, 31.0));
    }

    #[test]
    fn damaged_rayvis_files_fail_clearly() {
        let file = write(&small());
        for n in (0..file.len()).step_by(97) {
            assert!(read(&file[..n], "cut").is_err(), "cut at {n}");
        }
        // Every byte of the scene chunk's header and first part of its data flipped.
        for i in 32..700.min(file.len()) {
            let mut v = file.clone();
            v[i] ^= 0xff;
            let _ = read(&v, "flipped");
        }
        let no_rays = rdf::write(&rdf::read(&file).unwrap()[..1]);
        let e = read(&no_rays, "scene.rayvis").unwrap_err().to_string();
        assert!(e.contains("no RAYVIS_RAYTRACE chunk"), "{e}");
        let mut odd = rdf::read(&file).unwrap();
        odd[1].data.pop();
        let e = read(&rdf::write(&odd), "odd").unwrap_err().to_string();
        assert!(e.contains("52-byte records"), "{e}");
    }
}
