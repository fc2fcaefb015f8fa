#!/usr/bin/env python3
"""Writes the hand-made seed corpus of the fuzz targets into tests/fuzz/corpus/<reader>/ (the files are kept in the
repository; this script documents how they were made and can remake them). Every seed is a small, valid file (or a
deliberate corner case) in the format of its target. Seeds derived from the data sets of data/ are not kept here:
scripts/fuzz.sh makes them at run time from data.
"""
import gzip
import os
import shutil
import struct
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "corpus")
SPLIT = b"UVRSPLIT"


def put(reader, name, data):
    d = os.path.join(CORPUS, reader)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


# A unit cube split into 5 tetrahedra (8 points), and a single tetrahedron.
CUBE = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0), (0, 0, 1), (1, 0, 1), (0, 1, 1), (1, 1, 1)]
CUBE_TETS = [(0, 1, 2, 4), (1, 3, 2, 7), (1, 2, 4, 7), (2, 4, 7, 6), (1, 4, 5, 7)]
TET = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]


def vtk_legacy():
    pts = "\n".join(f"{x} {y} {z}" for x, y, z in CUBE)
    cells = "\n".join("4 " + " ".join(map(str, t)) for t in CUBE_TETS)
    put("vtk_legacy", "ascii_tets.vtk", f"""# vtk DataFile Version 3.0
cube
ASCII
DATASET UNSTRUCTURED_GRID
POINTS 8 float
{pts}
CELLS 5 25
{cells}
CELL_TYPES 5
10 10 10 10 10
CELL_DATA 5
SCALARS id int 1
LOOKUP_TABLE default
0 1 2 3 4
POINT_DATA 8
SCALARS s float 1
LOOKUP_TABLE default
0 1 2 3 4 5 6 7
VECTORS v double
{" ".join(["1 0 0"] * 8)}
FIELD FieldData 2
a%20b 1 8 float
0 1 2 3 4 5 6 7
c 2 8 int
{" ".join(["1 2"] * 8)}
METADATA
INFORMATION 0

""")
    # Mixed cells: a hexahedron, a wedge, a pyramid, a triangle and a vertex (tetrahedralized or skipped).
    put("vtk_legacy", "ascii_mixed.vtk", f"""# vtk DataFile Version 2.0
mixed
ASCII
DATASET UNSTRUCTURED_GRID
POINTS 8 double
{pts}
CELLS 5 28
8 0 1 3 2 4 5 7 6
6 0 1 2 4 5 6
5 0 1 3 2 4
3 0 1 2
1 7
CELL_TYPES 5
12
13
14
5
1
POINT_DATA 8
SCALARS s unsigned_char
LOOKUP_TABLE default
0 1 2 3 4 5 6 7
""")
    # Version 5.1: OFFSETS and CONNECTIVITY.
    put("vtk_legacy", "v51_offsets.vtk", f"""# vtk DataFile Version 5.1
v5
ASCII
DATASET UNSTRUCTURED_GRID
POINTS 4 float
0 0 0 1 0 0 0 1 0 0 0 1
CELLS 2 4
OFFSETS vtktypeint64
0 4
CONNECTIVITY vtktypeint64
0 1 2 3
CELL_TYPES 1
10
POINT_DATA 4
SCALARS s double 1
0.5 1.5 -2e3 1e-300
""")
    # BINARY: big-endian floats and ints right after the keyword lines.
    b = bytearray(b"# vtk DataFile Version 3.0\nbin\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n")
    for p in TET:
        b += struct.pack(">3f", *p)
    b += b"\nCELLS 1 5\n" + struct.pack(">5i", 4, 0, 1, 2, 3)
    b += b"\nCELL_TYPES 1\n" + struct.pack(">i", 10)
    b += b"\nPOINT_DATA 4\nSCALARS s short 1\nLOOKUP_TABLE default\n" + struct.pack(">4h", 0, 1, -2, 3)
    b += b"\nFIELD f 1\nstr 1 4 string\n" + b"".join(bytes([0xC0 | 2]) + b"ab" for _ in range(4))
    b += b"\nNORMALS n float\n" + struct.pack(">12f", *([0.0] * 12)) + b"\n"
    put("vtk_legacy", "binary_tet.vtk", bytes(b))
    # STRUCTURED_POINTS, ASCII and BINARY.
    put("vtk_legacy", "points_ascii.vtk", """# vtk DataFile Version 2.0
vol
ASCII
DATASET STRUCTURED_POINTS
DIMENSIONS 2 2 2
ORIGIN 0 0 0
SPACING 1 1 0.5
POINT_DATA 8
SCALARS v float
LOOKUP_TABLE default
0 1 2 3 4 5 6 7
""")
    b = bytearray(b"# vtk DataFile Version 1.0\nvol\n\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 3 2 2\n"
                  b"ASPECT_RATIO 1 1 1\nORIGIN 0 0 0\nPOINT_DATA 12\nSCALARS v unsigned_char\nLOOKUP_TABLE default\n")
    b += bytes(range(12)) + b"\nLOOKUP_TABLE t 2\n" + bytes(8) + b"\n"
    put("vtk_legacy", "points_binary.vtk", bytes(b))


def xml_array(name, typ, values, fmt, comps=1, header64=False, compress=False, big=False):
    """Returns (element text, appended bytes or None)."""
    code = {"Float32": "f", "Float64": "d", "Int32": "i", "Int64": "q", "UInt8": "B", "Int8": "b", "UInt16": "H",
            "Int16": "h", "UInt32": "I", "UInt64": "Q"}[typ]
    end = ">" if big else "<"
    raw = struct.pack(end + code * len(values), *values)
    hw = "Q" if header64 else "I"
    if compress:
        c = zlib.compress(raw)
        blob = struct.pack(end + hw * 4, 1, len(raw), len(raw), len(c)) + c
    else:
        blob = struct.pack(end + hw, len(raw)) + raw
    attrs = f'type="{typ}" Name="{name}" NumberOfComponents="{comps}" format="{fmt}"'
    if fmt == "ascii":
        return f'<DataArray {attrs}>{" ".join(map(str, values))}</DataArray>', None
    if fmt == "binary":
        import base64
        return f'<DataArray {attrs}>{base64.b64encode(blob).decode()}</DataArray>', None
    return f'<DataArray {attrs} offset="OFFSET"/>', blob


def xml_file(kind, body_arrays, fmt, header64=False, compress=False, big=False, appended_base64=False,
             wrap=None):
    """body_arrays: list of (placeholder, name, type, values, comps). wrap(elements) gives the inner XML."""
    appended = bytearray()
    elements = {}
    for key, name, typ, values, comps in body_arrays:
        text, blob = xml_array(name, typ, values, fmt, comps, header64, compress, big)
        if blob is not None:
            if appended_base64:
                import base64
                enc = base64.b64encode(blob)
                text = text.replace("OFFSET", str(len(appended)))
                appended += enc
            else:
                text = text.replace("OFFSET", str(len(appended)))
                appended += blob
        elements[key] = text
    attrs = f'type="{kind}" version="1.0" byte_order="{"BigEndian" if big else "LittleEndian"}"'
    attrs += f' header_type="{"UInt64" if header64 else "UInt32"}"'
    if compress:
        attrs += ' compressor="vtkZLibDataCompressor"'
    out = f'<?xml version="1.0"?>\n<VTKFile {attrs}>\n{wrap(elements)}\n'.encode()
    if fmt == "appended":
        enc = "base64" if appended_base64 else "raw"
        out += f'<AppendedData encoding="{enc}">\n_'.encode() + bytes(appended) + b"\n</AppendedData>\n"
    out += b"</VTKFile>\n"
    return out


def vtu():
    pts = [c for p in CUBE for c in p]
    conn = [i for t in CUBE_TETS for i in t]
    offs = [4 * (i + 1) for i in range(len(CUBE_TETS))]
    types = [10] * len(CUBE_TETS)
    arrays = [("P", "Points", "Float32", pts, 3), ("C", "connectivity", "Int64", conn, 1),
              ("O", "offsets", "Int64", offs, 1), ("T", "types", "UInt8", types, 1),
              ("S", "s", "Float64", [float(i) for i in range(8)], 1), ("I", "id", "Int32", list(range(8)), 1)]

    def wrap(e):
        return (f'<UnstructuredGrid><Piece NumberOfPoints="8" NumberOfCells="5">'
                f'<PointData Scalars="s">{e["S"]}{e["I"]}</PointData><CellData/>'
                f'<Points>{e["P"]}</Points><Cells>{e["C"]}{e["O"]}{e["T"]}</Cells></Piece></UnstructuredGrid>')

    put("vtu", "ascii.vtu", xml_file("UnstructuredGrid", arrays, "ascii", wrap=wrap))
    put("vtu", "binary.vtu", xml_file("UnstructuredGrid", arrays, "binary", wrap=wrap))
    put("vtu", "binary_zlib64.vtu", xml_file("UnstructuredGrid", arrays, "binary", header64=True, compress=True,
                                              wrap=wrap))
    put("vtu", "appended_raw.vtu", xml_file("UnstructuredGrid", arrays, "appended", wrap=wrap))
    put("vtu", "appended_raw_be.vtu", xml_file("UnstructuredGrid", arrays, "appended", big=True, header64=True,
                                               wrap=wrap))
    put("vtu", "appended_b64_zlib.vtu", xml_file("UnstructuredGrid", arrays, "appended", compress=True,
                                                 appended_base64=True, wrap=wrap))

    # Two pieces, the second with a hexahedron.
    def wrap2(e):
        piece = (f'<Piece NumberOfPoints="8" NumberOfCells="5"><PointData>{e["S"]}</PointData>'
                 f'<Points>{e["P"]}</Points><Cells>{e["C"]}{e["O"]}{e["T"]}</Cells></Piece>')
        hexa = ('<Piece NumberOfPoints="8" NumberOfCells="1"><PointData><DataArray type="Float64" Name="s" '
                'format="ascii">0 1 2 3 4 5 6 7</DataArray></PointData><Points><DataArray type="Float64" '
                'NumberOfComponents="3" format="ascii">' + " ".join(map(str, pts)) + '</DataArray></Points><Cells>'
                '<DataArray type="Int32" Name="connectivity" format="ascii">0 1 3 2 4 5 7 6</DataArray>'
                '<DataArray type="Int32" Name="offsets" format="ascii">8</DataArray>'
                '<DataArray type="UInt8" Name="types" format="ascii">12</DataArray></Cells></Piece>')
        return f"<UnstructuredGrid>{piece}{hexa}</UnstructuredGrid>"

    put("vtu", "two_pieces.vtu", xml_file("UnstructuredGrid", arrays, "ascii", wrap=wrap2))


def vti():
    vals = list(range(12))
    arrays = [("V", "v", "UInt8", vals, 1), ("W", "w", "Float32", [v * 0.5 for v in vals], 1)]

    def wrap(e):
        return (f'<ImageData WholeExtent="0 2 0 1 1 2" Origin="0 0 0" Spacing="1 1 0.5">'
                f'<Piece Extent="0 2 0 1 1 2"><PointData Scalars="w">{e["V"]}{e["W"]}</PointData><CellData/>'
                f'</Piece></ImageData>')

    put("vti", "ascii.vti", xml_file("ImageData", arrays, "ascii", wrap=wrap))
    put("vti", "binary.vti", xml_file("ImageData", arrays, "binary", wrap=wrap))
    put("vti", "binary_zlib.vti", xml_file("ImageData", arrays, "binary", compress=True, wrap=wrap))
    put("vti", "appended_raw.vti", xml_file("ImageData", arrays, "appended", big=True, wrap=wrap))
    put("vti", "appended_zlib64.vti", xml_file("ImageData", arrays, "appended", header64=True, compress=True,
                                               wrap=wrap))
    put("vti", "appended_b64.vti", xml_file("ImageData", arrays, "appended", appended_base64=True, wrap=wrap))

    def wrap_dir(e):
        return (f'<ImageData WholeExtent="0 1 0 1 0 2" Origin="1 2 3" Spacing="2 2 2" '
                f'Direction="0 1 0 1 0 0 0 0 1"><Piece><PointData>{e["V"]}</PointData></Piece></ImageData>')

    put("vti", "direction.vti", xml_file("ImageData", [("V", "v", "Int16", list(range(12)), 1)], "ascii",
                                         wrap=wrap_dir))


def tetgen():
    node = "# cube\n8 3 1 1\n" + "".join(f"{i + 1} {x} {y} {z} {i * 0.5} {i % 2}\n" for i, (x, y, z) in
                                          enumerate(CUBE))
    ele = "5 4 1\n" + "".join(f"{i + 1} " + " ".join(str(v + 1) for v in t) + f" {i}\n" for i, t in
                             enumerate(CUBE_TETS))
    put("tetgen", "cube_1based.txt", node.encode() + SPLIT + ele.encode())
    node0 = "4 3 0 0\n" + "".join(f"{i} {x} {y} {z}  # p{i}\n" for i, (x, y, z) in enumerate(TET))
    ele0 = "1 4 0\n0 0 2 1 3\n"  # inverted: re-oriented with a warning
    put("tetgen", "tet_0based.txt", node0.encode() + SPLIT + ele0.encode())
    put("tetgen", "quadratic.txt", node0.encode() + SPLIT + b"1 10 0\n0 0 1 2 3 0 1 2 3 0 1\n")


def off():
    pts = "".join(f"{x} {y} {z} {i}\n" for i, (x, y, z) in enumerate(CUBE))
    cells = "".join("4 " + " ".join(map(str, t)) + " 255 0 0\n" for t in CUBE_TETS)
    put("off", "cube_scalar.off", f"OFF\n# comment\n8 5 0\n{pts}\n{cells}")
    put("off", "tet_inline.off", "OFF 4 1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n4 0 1 2 3\n")
    put("off", "surface.off", "OFF\n3 1 3\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")


def plot3d_grid(dims, be=True, precision=4, iblank=False, grid_count=False, fortran=False):
    e = ">" if be else "<"
    n = dims[0] * dims[1] * dims[2]
    f = "f" if precision == 4 else "d"
    head = (struct.pack(e + "i", 1) if grid_count else b"") + struct.pack(e + "3i", *dims)
    coords = []
    for axis in range(3):
        for k in range(dims[2]):
            for j in range(dims[1]):
                for i in range(dims[0]):
                    coords.append(float((i, j, k)[axis]))
    body = struct.pack(e + f * (3 * n), *coords)
    if iblank:
        body += struct.pack(e + "i" * n, *([1] * n))
    if fortran:
        rec = lambda b: struct.pack(e + "i", len(b)) + b + struct.pack(e + "i", len(b))
        return rec(head) + rec(body)
    return head + body


def plot3d_q(dims, be=True, precision=4, grid_count=False, pad=0):
    e = ">" if be else "<"
    n = dims[0] * dims[1] * dims[2]
    f = "f" if precision == 4 else "d"
    head = (struct.pack(e + "i", 1) if grid_count else b"") + struct.pack(e + "3i", *dims)
    refs = struct.pack(e + f * 4, 2.95, 0.0, 2e6, 0.0)
    vals = [1.0 + 0.01 * i for i in range(5 * n)]
    return head + refs + struct.pack(e + f * (5 * n), *vals) + bytes(pad)


def plot3d():
    d = (2, 2, 2)
    put("plot3d", "be_single.bin", plot3d_grid(d) + SPLIT + plot3d_q(d))
    put("plot3d", "le_double_iblank.bin", plot3d_grid(d, be=False, precision=8, iblank=True) + SPLIT +
        plot3d_q(d, be=False, precision=8, pad=16))
    put("plot3d", "grid_count_fortran.bin", plot3d_grid((3, 2, 2), grid_count=True, fortran=True) + SPLIT +
        plot3d_q((3, 2, 2), grid_count=True))
    put("plot3d", "grid_only.xyz", plot3d_grid((2, 3, 2)))
    # A two-grid file: recognised and refused.
    two = struct.pack(">4i", 2, 2, 2, 2) + struct.pack(">3i", 2, 2, 2) + bytes(12 * 16)
    put("plot3d", "multigrid.xyz", two)


def nrrd():
    vals = bytes(range(24))
    put("nrrd", "raw_uchar.nrrd", b"NRRD0004\n# comment\ntype: uchar\ndimension: 3\nsizes: 2 3 4\n"
        b"spacings: 1 1 2\nencoding: raw\nkey:=value\n\n" + vals)
    shorts = struct.pack(">24h", *range(-12, 12))
    put("nrrd", "raw_short_be.nrrd", b"NRRD0005\ntype: short\ndimension: 3\nspace dimension: 3\nsizes: 2 3 4\n"
        b"space directions: (0.5,0,0) (0,0.5,0) (0,0,2)\nspace origin: (1,2,3)\nendian: big\nencoding: raw\n"
        b"byte skip: -1\n\n" + b"junk" + shorts)
    floats = struct.pack("<24f", *[i * 0.25 for i in range(24)])
    put("nrrd", "gzip_float.nrrd", b"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 3 4\nendian: little\n"
        b"encoding: gzip\n\n" + gzip.compress(floats))
    put("nrrd", "ascii_double.nrrd", b"NRRD0003\ntype: double\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n"
        b"line skip: 1\n\nskipped line\n0 1 2 3\n4 5 6 7.5e-1\n")
    put("nrrd", "lineskip_uint.nrrd", b"NRRD0001\ntype: unsigned int\ndimension: 3\nsizes: 1 1 2\nendian: little\n"
        b"encoding: raw\nline skip: 1\nbyte skip: 2\n\nxx\nyy" + struct.pack("<2I", 7, 9))
    # Detached forms whose data files are absent: the reader must fail with InputError.
    put("nrrd", "detached_series.nrrd", b"NRRD0004\ntype: short\ndimension: 3\nsizes: 4 4 3\nendian: little\n"
        b"encoding: raw\ndata file: slice.%03d 1 3 1 2\n")
    put("nrrd", "detached_list.nrrd", b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
        b"data file: LIST\na.raw\nb.raw\n")
    put("nrrd", "detached_self.nrrd", b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
        b"byte skip: -1\ndata file: input.nrrd\n\n" + bytes(8))


def mha():
    vals = bytes(range(24))
    put("mha", "uchar.mha", b"ObjectType = Image\nNDims = 3\nDimSize = 2 3 4\nElementSpacing = 1 1 2\n"
        b"Offset = 0 0 0\nTransformMatrix = 1 0 0 0 1 0 0 0 1\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n"
        + vals)
    shorts = struct.pack(">24h", *range(-12, 12))
    put("mha", "short_msb.mha", b"NDims = 3\nDimSize = 2 3 4\nElementByteOrderMSB = True\nHeaderSize = -1\n"
        b"BinaryData = True\nElementNumberOfChannels = 1\nElementType = MET_SHORT\nElementDataFile = LOCAL\n"
        b"padding" + shorts)
    floats = struct.pack("<24f", *[i * 0.25 for i in range(24)])
    c = zlib.compress(floats)
    put("mha", "zlib_float.mha", b"NDims = 3\nDimSize = 2 3 4\nCompressedData = True\nCompressedDataSize = " +
        str(len(c)).encode() + b"\nElementSize = 1 1 1\nElementType = MET_FLOAT\nElementDataFile = LOCAL\n" + c)
    put("mha", "detached.mha", b"NDims = 3\nDimSize = 2 2 2\nElementType = MET_DOUBLE\nElementDataFile = absent.raw\n")


def slc():
    nx, ny, nz = 3, 2, 2
    head = f"11111 {nx} {ny} {nz} 8\n1.0 1.0 2.0\n1 0 0 0\n2 1 X".encode()
    icon = bytes(3 * 2 * 1)
    raw = bytes(range(nx * ny * nz))
    put("slc", "raw.slc", head + icon + raw)
    rle_head = f"11111 {nx} {ny} {nz} 8\n1.0 1.0 2.0\n1 0 0 1\n0 0 X".encode()
    # slice 0: a literal run of 6; slice 1: a repeat run of 6 then the terminator.
    s0 = bytes([0x86]) + bytes(range(6)) + bytes([0])
    s1 = bytes([0x06, 9, 0])
    put("slc", "rle.slc", rle_head + f"{len(s0)} X".encode() + s0 + f" {len(s1)} X".encode() + s1)


def raw_volume():
    def head(dtype_index, big, dims):
        return bytes([dtype_index | (0x10 if big else 0)]) + struct.pack("<3i", *dims)
    put("raw_volume", "uint8_2x3x4", head(0, False, (2, 3, 4)) + bytes(range(24)))
    put("raw_volume", "int16_be", head(3, True, (2, 2, 2)) + struct.pack(">8h", *range(-4, 4)))
    put("raw_volume", "float64", head(7, False, (1, 2, 2)) + struct.pack("<4d", 0.5, -1, 2, 1e30))
    put("raw_volume", "float32_nan", head(6, False, (1, 1, 2)) + struct.pack("<2f", float("nan"), 1))
    put("raw_volume", "bogus_type", head(15, False, (1, 1, 1)) + b"x")
    put("raw_volume", "negative_dims", head(0, False, (-1, 2, 2)) + b"abcd")


def transfer_function():
    put("transfer_function", "extinction.json",
        '{"color": [[0, 0, 0, 1], [0.5, 0, 1, 0], [0.5, 1, 0, 0], [1, 1, 1, 1]], '
        '"extinction": [[0, 0], [0.3, 2.5], [1, 0.5]]}')
    put("transfer_function", "opacity.json",
        '{"color": [[0, 1, 1, 1]], "opacity": [[-1, 0], [2, 0.99]], "unit_distance": 0.1}')
    put("transfer_function", "paraview_preset.json",
        '[{"Name": "x", "RGBPoints": [0, 0.2, 0.3, 0.4, 1, 1, 0, 0]}]')
    put("transfer_function", "preset_under_color.json",
        '{"color": {"RGBPoints": [0, 0, 0, 0, 10, 1, 1, 1]}, "extinction": [[5, 1e3]]}')
    put("transfer_function", "top_level_preset.json",
        '{"RGBPoints": [-1e10, 0, 0, 0, 1e10, 1, 1, 1], "extinction": [[0, 1]]}')
    put("transfer_function", "bad_order.json", '{"color": [[1, 0, 0, 0], [0, 1, 1, 1]], "extinction": [[0, 1]]}')


def camera():
    put("camera", "perspective.json",
        '{"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fovy_deg": 45, "projection": "perspective"}')
    put("camera", "ortho.json",
        '{"eye": [1, 2, 3], "target": [0.5, 0.5, 0.5], "projection": "orthographic", "ortho_height": 2.5}')
    put("camera", "parallel_up.json", '{"eye": [0, 5, 0], "target": [0, 0, 0], "up": [0, 1, 0]}')
    put("camera", "tiny_up.json", '{"eye": [1e300, 0, 0], "target": [-1e300, 0, 0], "up": [0, 1e-300, 0]}')


def main():
    if os.path.isdir(CORPUS):
        shutil.rmtree(CORPUS)
    for f in (vtk_legacy, vtu, vti, tetgen, off, plot3d, nrrd, mha, slc, raw_volume, transfer_function, camera):
        f()
    return 0


if __name__ == "__main__":
    sys.exit(main())
