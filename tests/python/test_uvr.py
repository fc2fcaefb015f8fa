"""The Python module `uvr`: arrays in and out, every algorithm, errors, the worked example of docs/python.md.

Run by ctest ("python: the uvr module") with PYTHONPATH at the built module and UVR_BINARY at the built program, whose
output is what the module's renders must equal bit for bit.
"""
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import uvr

PROGRAM = os.environ["UVR_BINARY"]
SOURCE = os.environ["UVR_SOURCE_DIR"]

# metrics computed in NumPy in another order of summation than uvr's (pixel by pixel): only the last bits of the
# square root may differ, 1e-12 relative (as tests/test_compare_image.cpp).
MEASURE_RELATIVE = 1e-12

SMALL = dict(size=(48, 40), view=(30, 50))
SMALL_ARGS = ["--size", "48x40", "--view", "30,50"]


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("UVR_CACHE_DIR", str(tmp_path / "cache"))


def program_image(tmp_path, source, algo, *args):
    out = tmp_path / f"{algo}-{len(list(tmp_path.iterdir()))}.npy"
    subprocess.run([PROGRAM, "render", source, "--algo", algo, *args, "--out", str(out)], check=True,
                   capture_output=True)
    return np.load(out)


def same_bits(a, b):
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def test_a_render_is_an_h_by_w_by_4_float32_array_that_owns_no_copy():
    scene = uvr.Scene("builtin:torus-small", **SMALL)
    image = uvr.render(scene, "havs")
    assert image.shape == (40, 48, 4)
    assert image.dtype == np.float32
    assert image.flags["C_CONTIGUOUS"]
    # uvr's own buffer, handed over: NumPy did not allocate (and so did not copy) it.
    assert not image.flags["OWNDATA"]
    assert image.base is not None
    assert image[..., 3].max() > 0.1  # the torus is there


# Every algorithm on every backend it has, on the built-in mesh (the ray caster on the built-in volume): the module
# computes the program's bits.
CASES = [("builtin:torus-small", "reference", "cpu"), ("builtin:torus-small", "havs", "emu"),
         ("builtin:torus-small", "havs", "gl"), ("builtin:torus-small", "havs", "arb"),
         ("builtin:torus-small", "vicp", "emu"), ("builtin:torus-small", "vicp", "gl"),
         ("builtin:torus-volume", "raycast", "emu"), ("builtin:torus-volume", "raycast", "gl")]


def test_the_cases_cover_every_algorithm_and_backend():
    listed = {(a, b) for a, backends in uvr.algorithms().items() for b in backends}
    assert listed == {(a, b) for _, a, b in CASES}


@pytest.mark.parametrize("source,algo,backend", CASES)
def test_every_algorithm_renders_the_programs_bits(tmp_path, source, algo, backend):
    scene = uvr.Scene(source, **SMALL)
    options = {} if backend == "cpu" else {"backend": backend}
    mine = uvr.render(scene, algo, **options)
    args = SMALL_ARGS + ([] if backend == "cpu" else ["--backend", backend])
    assert same_bits(mine, program_image(tmp_path, source, algo, *args))
    assert mine[..., 3].max() > 0.05


def test_options_reach_the_renderer(tmp_path):
    scene = uvr.Scene("builtin:torus-small", **SMALL)
    mine, info = uvr.render(scene, "havs", k=2, segment="exact", interpolation="exact", with_stats=True)
    assert same_bits(mine, program_image(tmp_path, "builtin:torus-small", "havs", *SMALL_ARGS, "--k", "2",
                                         "--segment", "exact", "--interpolation", "exact"))
    assert not same_bits(mine, uvr.render(scene, "havs"))
    assert info["stats"]["k"] == 2
    assert info["ms"] > 0
    # k="all": every fragment held (the program's --k all), the bits of a k above the fullest pixel.
    every_k, every_k_info = uvr.render(scene, "havs", k="all", with_stats=True)
    assert every_k_info["stats"]["k"] == "all"
    assert same_bits(every_k, program_image(tmp_path, "builtin:torus-small", "havs", *SMALL_ARGS, "--k", "all"))
    assert same_bits(every_k, uvr.render(scene, "havs", k=255))  # more than this scene puts on a pixel
    facing = uvr.render(scene, "havs", k="all", ties="facing")
    assert same_bits(facing, program_image(tmp_path, "builtin:torus-small", "havs", *SMALL_ARGS, "--k", "all",
                                           "--ties", "facing"))
    # send reaches the GL driver: every face sent (none left out), the same bits as the covered ones alone.
    every, every_info = uvr.render(scene, "havs", backend="gl", send="all", with_stats=True)
    covered, covered_info = uvr.render(scene, "havs", backend="gl", with_stats=True)
    assert every_info["stats"]["send"] == "all" and every_info["stats"]["clip"]["uncovered"] == 0
    assert covered_info["stats"]["send"] == "covered" and covered_info["stats"]["clip"]["uncovered"] > 0
    assert same_bits(every, covered)
    # interpolation reaches the ray caster and VICP (the published pipelines by default, the exact variants by name).
    volume = uvr.Scene("builtin:torus-volume", **SMALL)
    ray_exact, ray_info = uvr.render(volume, "raycast", interpolation="exact", with_stats=True)
    assert ray_info["stats"]["interpolation"] == "exact" and "box" not in ray_info["stats"]
    assert same_bits(ray_exact, program_image(tmp_path, "builtin:torus-volume", "raycast", *SMALL_ARGS,
                                              "--interpolation", "exact"))
    assert uvr.render(volume, "raycast", with_stats=True)[1]["stats"]["interpolation"] == "gpu"
    vicp_published, vicp_info = uvr.render(scene, "vicp", with_stats=True)
    assert vicp_info["stats"]["interpolation"] == "gpu" and "wrong_exits" in vicp_info["stats"]
    assert same_bits(vicp_published, program_image(tmp_path, "builtin:torus-small", "vicp", *SMALL_ARGS))
    vicp_exact, vicp_exact_info = uvr.render(scene, "vicp", interpolation="exact", with_stats=True)
    assert vicp_exact_info["stats"]["interpolation"] == "exact" and "wrong_exits" not in vicp_exact_info["stats"]
    assert same_bits(vicp_exact, program_image(tmp_path, "builtin:torus-small", "vicp", *SMALL_ARGS,
                                               "--interpolation", "exact"))


def cube_arrays():
    """A unit cube split into five tetrahedra, scalar x + 2y + 3z, one tetrahedron written inverted."""
    points = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=np.float64)
    tets = np.array([[0, 1, 2, 4], [1, 3, 2, 7], [1, 4, 5, 7], [2, 6, 4, 7], [1, 2, 4, 7]])
    scalars = points @ np.array([1.0, 2.0, 3.0])
    return points, tets, scalars


def write_vtk(path, points, tets, scalars, cell_scalars=None):
    with open(path, "w") as f:
        f.write("# vtk DataFile Version 3.0\ncube\nASCII\nDATASET UNSTRUCTURED_GRID\n")
        f.write(f"POINTS {len(points)} double\n")
        f.writelines(f"{p[0]!r} {p[1]!r} {p[2]!r}\n" for p in points)
        f.write(f"CELLS {len(tets)} {5 * len(tets)}\n")
        f.writelines("4 " + " ".join(str(int(i)) for i in t) + "\n" for t in tets)
        f.write(f"CELL_TYPES {len(tets)}\n" + "10\n" * len(tets))
        f.write(f"POINT_DATA {len(points)}\nSCALARS s double 1\nLOOKUP_TABLE default\n")
        f.writelines(f"{v!r}\n" for v in scalars)
        if cell_scalars is not None:
            f.write(f"CELL_DATA {len(tets)}\nSCALARS c double 1\nLOOKUP_TABLE default\n")
            f.writelines(f"{v!r}\n" for v in cell_scalars)


def test_cell_values_and_per_cell_vertex_values_from_arrays_render_as_the_same_files(tmp_path):
    points, tets, scalars = cube_arrays()
    cell = np.array([0.1, 0.7, 0.3, 0.9, 0.5])
    write_vtk(tmp_path / "cells.vtk", points, tets, scalars, cell_scalars=cell)
    from_arrays = uvr.Scene(uvr.mesh(points, tets, scalars, name="s", cell_scalars={"c": cell}), field="c", **SMALL)
    from_file = uvr.Scene(str(tmp_path / "cells.vtk"), field="c", **SMALL)
    for algo in ("reference", "havs", "vicp"):
        assert same_bits(uvr.render(from_arrays, algo), uvr.render(from_file, algo)), algo
    # Per-cell vertex values (M x 4): each tetrahedron's own values, here jumping by 0.5 from one to the next; the
    # same as a file that writes every point once per tetrahedron.
    per_vertex = scalars[tets] + 0.5 * np.arange(len(tets))[:, None]
    write_vtk(tmp_path / "repeated.vtk", points[tets.reshape(-1)], np.arange(4 * len(tets)).reshape(-1, 4),
              per_vertex.reshape(-1))
    jumping = uvr.Scene(uvr.mesh(points, tets, per_vertex, name="s"), **SMALL)
    from_file = uvr.Scene(str(tmp_path / "repeated.vtk"), **SMALL)
    assert jumping.tetrahedra == 5
    for algo in ("reference", "havs", "vicp"):
        assert same_bits(uvr.render(jumping, algo), uvr.render(from_file, algo)), algo
    continuous = uvr.Scene(uvr.mesh(points, tets, scalars, name="s"), **SMALL)
    assert not same_bits(uvr.render(jumping, "reference"), uvr.render(continuous, "reference"))


def test_a_mesh_from_arrays_renders_as_the_same_mesh_read_from_a_file(tmp_path):
    points, tets, scalars = cube_arrays()
    write_vtk(tmp_path / "cube.vtk", points, tets, scalars)
    from_arrays = uvr.Scene(uvr.mesh(points, tets, scalars, name="s"), **SMALL)
    from_file = uvr.Scene(str(tmp_path / "cube.vtk"), **SMALL)
    assert from_arrays.tetrahedra == 5 and from_arrays.field == "s"
    for algo in ("reference", "havs", "vicp"):
        assert same_bits(uvr.render(from_arrays, algo), uvr.render(from_file, algo)), algo
    # Several fields by name: the scene picks one, as --field does.
    two = uvr.mesh(points, tets, {"s": scalars, "t": -scalars})
    assert uvr.Scene(two, field="t", **SMALL).field == "t"


def test_a_volume_from_arrays_renders_as_the_same_raw_file(tmp_path):
    z, y, x = np.mgrid[0:12, 0:10, 0:8].astype(np.float32)
    values = np.sin(x / 3) * np.cos(y / 4) + z / 12
    values.astype("<f4").tofile(tmp_path / "v.raw")
    from_arrays = uvr.Scene(uvr.volume(values, spacing=(1, 1, 1)), **SMALL)
    from_file = uvr.Scene(str(tmp_path / "v.raw"), dims=(8, 10, 12), dtype="float32", **SMALL)
    assert from_arrays.kind == "volume"
    for algo in ("reference", "raycast"):
        assert same_bits(uvr.render(from_arrays, algo), uvr.render(from_file, algo)), algo


def test_tf_and_camera_dicts_are_the_files_json(tmp_path):
    tf = {"color": [[0.0, 0.1, 0.2, 0.9], [1.0, 1.0, 0.8, 0.1]], "extinction": [[0.0, 0.5], [1.0, 4.0]]}
    camera = {"eye": [3.0, 2.0, 4.0], "target": [0.0, 0.0, 0.0], "up": [0.0, 1.0, 0.0], "fovy_deg": 35}
    import json
    (tmp_path / "tf.json").write_text(json.dumps(tf))
    (tmp_path / "cam.json").write_text(json.dumps(camera))
    scene = uvr.Scene("builtin:torus-small", tf=tf, camera=camera, size=(48, 40))
    expected = program_image(tmp_path, "builtin:torus-small", "havs", "--size", "48x40", "--tf",
                             str(tmp_path / "tf.json"), "--camera", str(tmp_path / "cam.json"))
    assert same_bits(uvr.render(scene, "havs"), expected)
    # A scene's camera and tf read back as dicts that make the same scene.
    again = uvr.Scene("builtin:torus-small", tf=scene.tf, camera=scene.camera, size=(48, 40))
    assert same_bits(uvr.render(again, "havs"), expected)


def numpy_measures(image, reference, channels=4):
    diff = np.abs(image[..., :channels].astype(np.float64) - reference[..., :channels].astype(np.float64))
    worst = diff.max(axis=2)
    covered = reference[..., 3].astype(np.float64) > 1.0 / 255.0
    empty = covered & np.all(image[..., :channels] == 0, axis=2)
    return {"rmse": math.sqrt(np.mean(diff ** 2)), "max_abs": float(worst.max()),
            "visible_fraction": float(np.mean(worst > 1.0 / 255.0)),
            "covered_left_empty": float(empty.sum() / covered.sum())}


def test_measure_gives_spec_4_as_numpy_computes_it():
    reference = uvr.reference(uvr.Scene("builtin:torus-small", **SMALL))
    rng = np.random.default_rng(27)
    bent = reference + rng.normal(0.0, 0.004, reference.shape).astype(np.float32)
    bent[::3, ::5] = 0.0  # dropped fragments
    got = uvr.measure(bent, reference)
    for key, value in numpy_measures(bent, reference).items():
        assert got[key] == pytest.approx(value, rel=MEASURE_RELATIVE), key
    assert got["psnr"] == pytest.approx(20 * math.log10(1 / got["rmse"]), rel=MEASURE_RELATIVE)
    assert uvr.measure(reference, reference)["psnr"] == math.inf
    # Colour only (H x W x 3): against the reference's premultiplied colour, i.e. its colour over black.
    colour = np.ascontiguousarray(bent[..., :3])
    got3 = uvr.measure(colour, reference)
    for key, value in numpy_measures(bent, reference, channels=3).items():
        assert got3[key] == pytest.approx(value, rel=MEASURE_RELATIVE), key
    # Any array NumPy can turn into float32 is accepted: float64, a strided view.
    assert uvr.measure(bent.astype(np.float64), reference)["rmse"] == pytest.approx(got["rmse"], rel=MEASURE_RELATIVE)


def test_budget_gives_the_programs_budget(tmp_path):
    """uvr.budget writes the report `uvr budget` writes and returns its budget.json: the same numbers, the same images."""
    import json
    scene = uvr.Scene("builtin:torus-small", **SMALL)
    mine = uvr.budget(scene, "vicp", report=str(tmp_path / "py"))
    assert mine == json.loads((tmp_path / "py" / "budget.json").read_text())
    assert mine["baseline_ok"] and mine["factor_order"] == ["sort", "table", "interpolation", "coverage", "termination"]
    subprocess.run([PROGRAM, "budget", "builtin:torus-small", "--algo", "vicp", *SMALL_ARGS, "--report",
                    str(tmp_path / "program")], check=True, capture_output=True)
    theirs = json.loads((tmp_path / "program" / "budget.json").read_text())
    for run in ("baseline", "total"):
        assert mine[run]["rmse"] == theirs[run]["rmse"]
    for name in mine["factor_order"]:
        assert mine["factors"][name]["rmse"] == theirs["factors"][name]["rmse"]
        assert same_bits(np.load(tmp_path / "py" / "runs" / f"{name}.npy"),
                         np.load(tmp_path / "program" / "runs" / f"{name}.npy"))
    with pytest.raises(uvr.Error, match="--algo must be havs, vicp or raycast|algo must be havs, vicp or raycast"):
        uvr.budget(scene, "reference", report=str(tmp_path / "never"))


def test_verify_gives_the_programs_orders(tmp_path):
    """uvr.verify returns the JSON `uvr verify --json` prints: the same levels and orders; uvr.verify_images recovers
    the order of a synthetic sequence (docs/verification.md)."""
    import json
    scene = uvr.Scene("builtin:torus-small", **SMALL)
    mine = uvr.verify(scene, "havs", "table", isolate=True)
    theirs = json.loads(subprocess.run([PROGRAM, "verify", "builtin:torus-small", *SMALL_ARGS, "--algo", "havs",
                                        "--refine", "table", "--isolate", "--json"],
                                       check=True, capture_output=True, text=True).stdout)
    assert mine["measures"] == theirs["measures"]
    assert mine["verdict"] == theirs["verdict"] == "pass"
    # The refinements that make their own scenes: the image's size (the scene keeps its own) and the mesh.
    for source, refine in (("builtin:torus-small", "size"), ("builtin:grid-4", "mesh")):
        scene = uvr.Scene(source, size=(24, 20), view=(30, 50))
        mine = uvr.verify(scene, "reference", refine, levels=3)
        theirs = json.loads(subprocess.run([PROGRAM, "verify", source, "--size", "24x20", "--view", "30,50", "--algo",
                                            "reference", "--refine", refine, "--levels", "3", "--json"],
                                           check=True, capture_output=True, text=True).stdout)
        assert mine["measures"] == theirs["measures"], refine
        assert (scene.width, scene.height) == (24, 20)
    with pytest.raises(uvr.Error, match="builtin:grid-N"):
        uvr.verify(uvr.Scene("builtin:torus-small", **SMALL), "reference", "mesh")
    reference = np.full((8, 8, 4), 0.5, dtype=np.float32)
    h = [1.0, 0.5, 0.25, 0.125]
    images = [reference + np.float32(0.01 * x * x) for x in h]
    got = uvr.verify_images(images, h, reference=reference, expected=2)
    assert got["measures"]["rmse"]["order"] == pytest.approx(2.0, abs=0.05)
    assert got["verdict"] == "pass"
    with pytest.raises(uvr.Error, match="one h per image"):
        uvr.verify_images(images, h[:3], reference=reference)


def test_bad_input_raises_uvr_error_with_uvrs_message(tmp_path):
    assert issubclass(uvr.Error, ValueError)
    scene = uvr.Scene("builtin:torus-small", **SMALL)
    points, tets, scalars = cube_arrays()
    (tmp_path / "broken.vtk").write_text("# vtk DataFile Version 3.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3\n")
    cases = [
        (lambda: uvr.Scene(str(tmp_path / "missing.vtk")), "missing.vtk"),
        (lambda: uvr.Scene(str(tmp_path / "broken.vtk")), "broken.vtk"),
        (lambda: uvr.render(scene, "splatting"), "splatting"),
        (lambda: uvr.render(scene, "havs", kay=6), "unknown option 'kay'"),
        (lambda: uvr.render(scene, "havs", backend="arb", k=4), "k is 6"),
        (lambda: uvr.mesh(points[:, :2], tets, scalars), "points must be an N x 3 array"),
        (lambda: uvr.mesh(points, tets + 10, scalars), "out of range"),
        (lambda: uvr.mesh(points, tets.astype(float), scalars), "array of integers"),
        (lambda: uvr.mesh(np.where(points == 1, np.nan, points), tets, scalars), "arrays"),
        (lambda: uvr.mesh(points, tets, scalars[:-1]), "arrays"),
        (lambda: uvr.mesh(points, tets, np.zeros((4, 4))), "4 rows for 5 tetrahedra"),
        (lambda: uvr.mesh(points, tets, cell_scalars=np.zeros(4)), "4 values for 5 tetrahedra"),
        (lambda: uvr.mesh(points, tets), "no scalar field given"),
        (lambda: uvr.volume(np.zeros((4, 4))), "Z x Y x X"),
        (lambda: uvr.Scene("builtin:torus-small", size=(0, 10)), "size"),
        (lambda: uvr.render(scene, "havs", k=0), "k must be a whole number of at least 1, or all, not '0'"),
        (lambda: uvr.render(scene, "havs", k="every"), "k must be a whole number of at least 1, or all, not 'every'"),
        (lambda: uvr.render(scene, "havs", k=True), "option 'k' has the wrong type"),
        (lambda: uvr.render(scene, "havs", preintegrate=1), "option 'preintegrate' has the wrong type"),
        (lambda: uvr.render(scene, "havs", entries="seed"), "entries seed is now spelled entries paper"),
        (lambda: uvr.render(scene, "havs", threshold=1.5), "threshold must be a number in [0, 1], not '1.5'"),
        (lambda: uvr.render(scene, "havs", ties="facing"), "ties facing needs k all"),
        (lambda: uvr.render(scene, "havs", k="all", ties="first"), "ties must be arrival or facing"),
        (lambda: uvr.render(scene, "havs", backend="gl", send="some"), "send must be covered or all"),
        (lambda: uvr.render(scene, "havs", table_size=1), "table_size"),
        (lambda: uvr.Scene("builtin:torus-small", tf={"color": []}), "tf (dict)"),
        (lambda: uvr.Scene("builtin:torus-small", camera=scene.camera, view=(1, 2)), "not both"),
        (lambda: uvr.measure(np.zeros((4, 4, 4), np.float32), np.zeros((4, 5, 4), np.float32)), "cannot compare"),
        (lambda: uvr.measure(np.zeros((4, 4)), np.zeros((4, 4, 4))), "H x W x 4"),
    ]
    for call, phrase in cases:
        with pytest.raises(uvr.Error) as e:
            call()
        assert phrase in str(e.value)
        # Options are named as Python passes them (table_size), never as the program's --table-size.
        assert "--" not in str(e.value), str(e.value)


def python_blocks(path):
    return re.findall(r"```python\n(.*?)```", open(path).read(), flags=re.S)


def help_options(command):
    text = subprocess.run([PROGRAM, command, "--help"], capture_output=True, text=True, check=True).stdout
    return set(re.findall(r"^\s+(--[a-z][a-z0-9-]*)", text, flags=re.M))


def test_every_algorithm_option_of_the_program_is_a_keyword_and_back():
    # One table builds both: render's options less the input, scene and command ones are exactly the keywords' options.
    keywords = uvr.options()
    table = {o["option"] for o in keywords.values()}
    scene = help_options("info") | {"--tf", "--camera", "--view", "--size", "--json", "--help"}
    own = {"render": {"--algo", "--out", "--diagnostics"}, "compare": {"--algos", "--report", "--image", "--label"},
           "budget": {"--algo", "--report"}}
    for command, options in own.items():
        assert help_options(command) - scene - options == table, command
    # The keyword is the option with '_' for '-', but for the cache switch, which Python turns around.
    for key, o in keywords.items():
        expected = "cache" if o["option"] == "--no-cache" else o["option"][2:].replace("-", "_")
        assert key == expected
    assert keywords["cache"]["inverted"] and keywords["cache"]["switch"]


def test_a_renamed_value_works_under_its_new_name_and_the_old_one_is_refused(tmp_path):
    scene = uvr.Scene("builtin:torus-small", **SMALL)
    paper = uvr.render(scene, "havs", entries="paper")
    assert same_bits(paper, program_image(tmp_path, "builtin:torus-small", "havs", *SMALL_ARGS, "--entries", "paper"))
    assert not same_bits(paper, uvr.render(scene, "havs", entries="marked"))
    with pytest.raises(uvr.Error, match="entries seed is now spelled entries paper"):
        uvr.render(scene, "havs", entries="seed")


def test_the_worked_example_of_docs_python_md_runs(tmp_path):
    blocks = python_blocks(os.path.join(SOURCE, "docs", "python.md"))
    assert len(blocks) >= 3
    script = tmp_path / "example.py"
    script.write_text("\n".join(blocks))
    env = dict(os.environ, MPLBACKEND="Agg")
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "havs-error-vs-k.png").stat().st_size > 1000
