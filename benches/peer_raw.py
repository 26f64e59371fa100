#!/usr/bin/env python3
"""A volume as the peer harness's raw file and JSON sidecar, with plain python3 (no numpy,
pynrrd or nibabel), for a machine where VTK is present but the peer's venv is not.

    python3 benches/peer_raw.py VOLUME OUT.json

VOLUME: an NRRD with an attached header (raw or gzip encoding) or a NIfTI-1 file (.nii or
.nii.gz). Writes OUT.raw (little-endian, x fastest, as on disk) and OUT.json with the keys
vtk_render.py reads: file, dims, dtype, spacing, value_range. The harness's own reader (pynrrd,
nibabel) gives the same bytes: both keep the file's voxel order and read spacing as the length of
each axis's space direction (NRRD) or pixdim (NIfTI).
"""
import array
import gzip
import json
import math
import os
import struct
import sys

NRRD_TYPES = {
    "uchar": "uint8", "unsigned char": "uint8", "uint8": "uint8", "uint8_t": "uint8",
    "signed char": "int8", "int8": "int8", "int8_t": "int8",
    "short": "int16", "int16": "int16", "int16_t": "int16", "signed short": "int16",
    "ushort": "uint16", "unsigned short": "uint16", "uint16": "uint16", "uint16_t": "uint16",
    "int": "int32", "int32": "int32", "int32_t": "int32", "signed int": "int32",
    "float": "float32", "double": "float64",
}
# NIfTI datatype codes: uint8, int16, int32, float32, float64, int8, uint16.
NIFTI_TYPES = {2: "uint8", 4: "int16", 8: "int32", 16: "float32", 64: "float64", 256: "int8",
               512: "uint16"}
ARRAY_CODES = {"uint8": "B", "int8": "b", "int16": "h", "uint16": "H", "int32": "i",
               "float32": "f", "float64": "d"}


def read_nrrd(path):
    raw = open(path, "rb").read()
    end = raw.index(b"\n\n") + 2
    fields = {}
    for line in raw[:end].decode("latin-1").splitlines()[1:]:
        if ":" in line and not line.startswith("#"):
            key, value = line.split(":", 1)
            fields[key.strip()] = value.lstrip("=").strip()
    dims = [int(v) for v in fields["sizes"].split()]
    if "space directions" in fields:
        axes = fields["space directions"].replace("(", " ").replace(")", " ").split()
        vectors = [[float(c) for c in a.split(",")] for a in axes if a != "none"]
        spacing = [math.sqrt(sum(c * c for c in v)) for v in vectors]
    else:
        spacing = [float(v) for v in fields.get("spacings", "1 1 1").split()]
    data = raw[end:]
    if fields.get("encoding") in ("gzip", "gz"):
        data = gzip.decompress(data)
    elif fields.get("encoding") != "raw":
        sys.exit(f"{path}: encoding {fields.get('encoding')} not handled here")
    big = fields.get("endian") == "big"
    return dims, NRRD_TYPES[fields["type"]], spacing, data, big


def read_nifti(path):
    raw = open(path, "rb").read()
    if path.endswith(".gz"):
        raw = gzip.decompress(raw)
    big = struct.unpack("<i", raw[:4])[0] != 348
    e = ">" if big else "<"
    dim = struct.unpack(e + "8h", raw[40:56])
    datatype = struct.unpack(e + "h", raw[70:72])[0]
    pixdim = struct.unpack(e + "8f", raw[76:108])
    offset = int(struct.unpack(e + "f", raw[108:112])[0])
    dims = list(dim[1:4])
    dtype = NIFTI_TYPES[datatype]
    count = dims[0] * dims[1] * dims[2] * array.array(ARRAY_CODES[dtype]).itemsize
    return dims, dtype, [float(p) for p in pixdim[1:4]], raw[offset:offset + count], big


def main():
    src, out = sys.argv[1:3]
    if src.endswith((".nii", ".nii.gz")):
        dims, dtype, spacing, data, big = read_nifti(src)
    else:
        dims, dtype, spacing, data, big = read_nrrd(src)
    values = array.array(ARRAY_CODES[dtype])
    values.frombytes(data[:dims[0] * dims[1] * dims[2] * values.itemsize])
    if big != (sys.byteorder == "big"):
        values.byteswap()
    if sys.byteorder == "big":
        little = array.array(values.typecode, values)
        little.byteswap()
    else:
        little = values
    raw_path = os.path.splitext(out)[0] + ".raw"
    with open(raw_path, "wb") as f:
        little.tofile(f)
    meta = {"file": os.path.basename(raw_path), "dims": dims, "dtype": dtype,
            "spacing": spacing, "value_range": [float(min(values)), float(max(values))]}
    with open(out, "w") as f:
        json.dump(meta, f)


if __name__ == "__main__":
    main()
