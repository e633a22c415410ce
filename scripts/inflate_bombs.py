# Decompression bombs for `scripts/hostile-sweep --bombs` (issue 48, item 2): each a small file
# (at most a few MB) whose compressed data inflates to, or claims, far more. Written into a
# folder by write_bombs(folder); each entry is (file, what it is, the intermix command reading it).
import base64
import json
import os
import struct
import zipfile
import zlib
import bz2

GIB = 1 << 30


def deflated_zeros(n, wbits=15, level=9):
    """n zero bytes deflated (zlib wrapper for wbits 15, gzip for 31, raw for -15)."""
    c = zlib.compressobj(level, zlib.DEFLATED, wbits)
    chunk, parts = bytes(1 << 22), []
    while n > 0:
        k = min(n, len(chunk))
        parts.append(c.compress(chunk[:k]))
        n -= k
    parts.append(c.flush())
    return b"".join(parts)


def gzip_of_zeros_after(head, zeros):
    """A gzip member of `head` then `zeros` zero bytes (a multiple of 64 MiB), built from one
    full-flushed deflate block repeated: an 8 GiB stream in 8 MB, its CRC right."""
    unit = 64 << 20
    assert zeros % unit == 0
    c = zlib.compressobj(9, zlib.DEFLATED, -15)
    first = c.compress(head) + c.flush(zlib.Z_FULL_FLUSH)
    c2 = zlib.compressobj(9, zlib.DEFLATED, -15)
    block = c2.compress(bytes(unit)) + c2.flush(zlib.Z_FULL_FLUSH)
    crc, z = zlib.crc32(head), bytes(unit)
    for _ in range(zeros // unit):
        crc = zlib.crc32(z, crc)
    body = first + block * (zeros // unit) + b"\x03\x00"  # an empty final block
    return (b"\x1f\x8b\x08\x00\x00\x00\x00\x00\x02\xff" + body +
            struct.pack("<II", crc & 0xFFFFFFFF, (len(head) + zeros) & 0xFFFFFFFF))


def nifti1_header(dims, datatype, bitpix):
    h = bytearray(348)
    struct.pack_into("<i", h, 0, 348)
    struct.pack_into("<8h", h, 40, 3, *dims, 1, 1, 1, 1)
    struct.pack_into("<hh", h, 70, datatype, bitpix)
    struct.pack_into("<8f", h, 76, 1, 1, 1, 1, 1, 1, 1, 1)
    struct.pack_into("<f", h, 108, 352.0)  # vox_offset
    struct.pack_into("<h", h, 252, 1)  # qform_code
    struct.pack_into("<f", h, 256, 1.0)  # quatern_d (unused with qfac)
    h[344:348] = b"n+1\0"
    return bytes(h) + bytes(4)


def vtp_shared_block(points, arrays):
    block = deflated_zeros(points * 12)
    appended = struct.pack("<IIII", 1, points * 12, 0, len(block)) + block
    data = "".join(f'<DataArray type="Float32" Name="a{i}" NumberOfComponents="3" '
                   f'format="appended" offset="0"/>' for i in range(arrays))
    return (f'<?xml version="1.0"?>\n<VTKFile type="PolyData" version="1.0" byte_order='
            f'"LittleEndian" header_type="UInt32" compressor="vtkZLibDataCompressor">\n'
            f'<PolyData><Piece NumberOfPoints="{points}" NumberOfPolys="1">\n<Points>'
            f'<DataArray type="Float32" NumberOfComponents="3" format="appended" offset="0"/>'
            f'</Points>\n<Polys><DataArray type="Int32" Name="connectivity" format="ascii">'
            f'0 1 2</DataArray><DataArray type="Int32" Name="offsets" format="ascii">3'
            f'</DataArray></Polys>\n<PointData>{data}</PointData>\n</Piece></PolyData>\n'
            f'<AppendedData encoding="raw">\n_').encode() + appended + \
        b"\n</AppendedData>\n</VTKFile>\n"


def gifti_array(intent, dtype, dims, payload):
    dim = " ".join(f'Dim{i}="{d}"' for i, d in enumerate(dims))
    return (f'<DataArray Intent="NIFTI_INTENT_{intent}" DataType="NIFTI_TYPE_{dtype}" '
            f'ArrayIndexingOrder="RowMajorOrder" Dimensionality="{len(dims)}" {dim} '
            f'Encoding="GZipBase64Binary" Endian="LittleEndian" ExternalFileName="" '
            f'ExternalFileOffset=""><Data>{payload}</Data></DataArray>\n')


def gifti(arrays):
    return ('<?xml version="1.0" encoding="UTF-8"?>\n<GIFTI Version="1.0" '
            f'NumberOfDataArrays="{len(arrays)}">\n' + "".join(arrays) + "</GIFTI>\n")


def write_bombs(folder):
    """Writes the bombs; returns [(file, description, command)]."""
    out = []

    def put(name, data, what):
        file = os.path.join(folder, name)
        with open(file, "wb") as f:
            f.write(data)
        # Volumes are rendered: a grid too large to hold is rendered in bricks, where the reading
        # of compressed data went wrong; `info` reads only the header of such a grid.
        volume = not name.endswith((".vtp", ".gii"))
        out.append((file, what, render(file) if volume else ["info", file]))

    def render(file):
        return ["render", file, "--width", "16", "--height", "16", "-o",
                os.path.join(folder, "out.png")]

    put("shared.vtp", vtp_shared_block(2 << 20, 20),
        "VTK XML: 21 arrays name one compressed block of 24 MiB")
    gib = base64.b64encode(deflated_zeros(GIB)).decode()
    tri = gifti_array("TRIANGLE", "INT32", [1, 3],
                      base64.b64encode(zlib.compress(struct.pack("<3i", 0, 1, 2))).decode())
    put("points.gii", gifti([gifti_array("POINTSET", "FLOAT32", [GIB // 12, 3], gib), tri])
        .encode(), "GIfTI: a 1 GiB gzip-base64 POINTSET")
    small = gifti_array("POINTSET", "FLOAT32", [3, 3],
                        base64.b64encode(zlib.compress(bytes(36))).decode())
    put("four.gii", gifti([gifti_array("SHAPE", "FLOAT32", [GIB // 4], gib)] * 4 + [small, tri])
        .encode(), "GIfTI: four 1 GiB gzip-base64 arrays beside a surface")
    put("claims8g.nii.gz", gzip_of_zeros_after(nifti1_header((2048, 2048, 2048), 2, 8), 8 * GIB),
        "NIfTI: 8 GiB of gzip voxels in 8 MB")
    put("claims1g.nii.gz", gzip_of_zeros_after(nifti1_header((1024, 1024, 1024), 2, 8), GIB),
        "NIfTI: 1 GiB of gzip voxels")
    nrrd = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1024 1024 1024\nencoding: {}\n\n"
    put("gzip.nrrd", nrrd.format("gzip").encode() + deflated_zeros(GIB, 31),
        "NRRD: 1 GiB of gzip voxels")
    put("bzip2.nrrd", nrrd.format("bzip2").encode() + bz2.compress(bytes(GIB), 9),
        "NRRD: 1 GiB of bzip2 voxels")
    mha = ("ObjectType = Image\nNDims = 3\nDimSize = 1024 1024 1024\nElementType = MET_UCHAR\n"
           "CompressedData = True\nElementDataFile = LOCAL\n")
    put("zlib.mha", mha.encode() + deflated_zeros(GIB), "MetaImage: 1 GiB of zlib voxels")
    mgh = bytearray(284)
    struct.pack_into(">7i", mgh, 0, 1, 1024, 1024, 1024, 1, 0, 0)  # uchar, 1 frame
    put("gzip.mgz", gzip_of_zeros_after(bytes(mgh), GIB),
        "MGH: 1 GiB of gzip voxels")
    def ome_zarr(name, shape, chunks, files):
        zarr = os.path.join(folder, name)
        os.makedirs(os.path.join(zarr, "0"))
        with open(os.path.join(zarr, ".zattrs"), "w") as f:
            json.dump({"multiscales": [{"version": "0.4", "axes": [
                {"name": a, "type": "space"} for a in "zyx"], "datasets": [
                {"path": "0", "coordinateTransformations": [{"type": "scale",
                                                             "scale": [1, 1, 1]}]}]}]}, f)
        with open(os.path.join(zarr, ".zgroup"), "w") as f:
            json.dump({"zarr_format": 2}, f)
        with open(os.path.join(zarr, "0", ".zarray"), "w") as f:
            json.dump({"zarr_format": 2, "shape": shape, "chunks": chunks, "dtype": "|u1",
                       "order": "C", "fill_value": 0, "compressor": {"id": "gzip", "level": 1},
                       "filters": None}, f)
        for chunk, data in files.items():
            with open(os.path.join(zarr, "0", chunk), "wb") as f:
                f.write(data)
        return zarr

    # OME-Zarr: a chunk of 64^3 bytes whose gzip stream inflates to 128 MiB (in a file no
    # larger than an honest chunk may be).
    zarr = ome_zarr("chunk.zarr", [64, 64, 64], [64, 64, 64],
                    {"0.0.0": deflated_zeros(128 << 20, 31)})
    out.append((zarr, "OME-Zarr: a 256 KiB chunk whose gzip data inflates to 128 MiB",
                render(zarr)))
    # OME-Zarr: two layers of honest 128 MiB chunks, each within the budget, decoded at once.
    layer = deflated_zeros(128 << 20, 31)
    zarr = ome_zarr("layers.zarr", [256, 1024, 1024], [128, 1024, 1024],
                    {"0.0.0": layer, "1.0.0": layer})
    out.append((zarr, "OME-Zarr: two layers of 128 MiB chunks in 260 KB", render(zarr)))
    # TRX: positions of 1 GiB of zeros, deflated, the directory telling the truth.
    n, v = 1, GIB // 12
    header = json.dumps({"DIMENSIONS": [1, 1, 1], "NB_STREAMLINES": n, "NB_VERTICES": v,
                         "VOXEL_TO_RASMM": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0],
                                            [0, 0, 0, 1]]})
    trx = os.path.join(folder, "positions.trx")
    with zipfile.ZipFile(trx, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as z:
        z.writestr("header.json", header)
        z.writestr("offsets.uint64", struct.pack("<2Q", 0, v))
        with z.open("positions.3.float32", "w", force_zip64=True) as f:
            left, zeros = v * 12, bytes(1 << 22)
            while left > 0:
                f.write(zeros[:min(left, len(zeros))])
                left -= min(left, len(zeros))
    out.append((trx, "TRX: 1 GiB of positions deflated in a zip", render(trx)))
    return out
