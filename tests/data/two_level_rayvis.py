#!/usr/bin/env python3
"""Writes tests/data/two_level.rayvis (and cycle.rayvis, the same with the grandchild naming
its parent as its child): a .rayvis file with a node hierarchy two levels deep,
written from RayVis's listings A.1/A.2 and the RDF specification directly (struct.pack), not
by Voxcast's own writer, so the reader is checked against an independent one.

The scene: one mesh (a triangle (0,0,0), (1,0,0), (0,1,0)); a root node without a mesh,
translated by (10, 0, 0); its child, with the mesh, scaled by 2 and translated by (0, 5, 0);
the child's child, with the mesh, turned 90 degrees about z and translated by (0, 0, 3).
Composed from the root down, the child's triangle lies at (10,5,0), (12,5,0), (10,7,0) and
the grandchild's at (10,5,6), (10,7,6), (8,5,6). One trace (id 7) of one ray.

Run: python3 tests/data/two_level_rayvis.py (it writes the file beside itself).
"""
import os
import struct


def matrix(rows):
    """A 4x4 matrix given as rows (acting on column vectors), stored row-major."""
    return b"".join(struct.pack("<4f", *r) for r in rows)


def node(node_id, mesh_id, children, rows):
    record = struct.pack("<QQ3fiB3x", len(children), mesh_id, 0.8, 0.8, 0.8, node_id, 0xFF)
    record += matrix(rows) + b"\0" * 4
    assert len(record) == 104, len(record)
    return record + b"".join(struct.pack("<I", c) for c in children)


NO_MESH = 0xFFFFFFFFFFFFFFFF
# The mesh: one primitive, three vertices of 12 bytes, three u32 indices.
vertices = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
indices = struct.pack("<3I", 0, 1, 2)
mesh = struct.pack("<Q", 1) + struct.pack("<QQQQ", 12, 3, 4, 3) + vertices + indices


def write(name, grandchild_children):
    nodes = (
        node(0, NO_MESH, [1], [(1, 0, 0, 10), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1)])
        + node(1, 0, [2], [(2, 0, 0, 0), (0, 2, 0, 5), (0, 0, 2, 0), (0, 0, 0, 1)])
        + node(2, 0, grandchild_children, [(0, -1, 0, 0), (1, 0, 0, 0), (0, 0, 1, 3), (0, 0, 0, 1)])
    )
    rdf(name, nodes)


def rdf(name, nodes):
    scene_header = struct.pack("<QQ", 1, 1)  # meshCount, rootNodeCount
    scene_data = mesh + struct.pack("<QQ", 3, 0) + nodes  # nodeCount, rootNodeId
    trace_header = struct.pack("<I", 7)
    trace_data = struct.pack("<I3ff3fff3I", 0, 0, 0, -5, 0.0, 0, 0, 1, 100.0, 5.0, 0, 0, 0)
    assert len(trace_data) == 52

    chunks = [
        (b"RAYVIS_SCENE", scene_header, scene_data),
        (b"RAYVIS_RAYTRACE", trace_header, trace_data),
    ]
    body = bytearray(b"\0" * 32)
    entries = b""
    for ident, header, data in chunks:
        header_at = len(body)
        body += header
        data_at = len(body)
        body += data
        entries += ident.ljust(16, b"\0") + struct.pack("<B3xI", 0, 1)
        entries += struct.pack("<5q", header_at, len(header), data_at, len(data), 0)
    index_at = len(body)
    body += entries
    body[0:32] = b"AMD_RDF " + struct.pack("<II", 3, 0) + struct.pack("<qq", index_at, len(entries))
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), name)
    with open(out, "wb") as f:
        f.write(bytes(body))
    print(out, len(body), "bytes")


write("two_level.rayvis", [])
write("cycle.rayvis", [1])
