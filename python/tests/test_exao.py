"""Tests of the exao Python module: equality with the C++ API and `exao query`, bad input, the
GIL, progress and cancelling, and exao.bake / exao.render. Run by CTest (python_module) with
PYTHONPATH at the build tree's package and EXAO_BINARY / EXAO_API_REFERENCE set."""

import os
import struct
import subprocess
import threading

import numpy as np
import pytest

import exao


# --- Scenes and receivers the tests make ----------------------------------------------------


def boxes_scene(seed=1, boxes=12):
    """A 10 x 10 ground (8 x 8 quads) with `boxes` random boxes on it: (vertices, faces)."""
    rng = np.random.default_rng(seed)
    vertices, faces = [], []

    def quad(a, b, c, d):
        base = len(vertices)
        vertices.extend([a, b, c, d])
        faces.extend([(base, base + 1, base + 2), (base, base + 2, base + 3)])

    g = np.linspace(-5.0, 5.0, 9)
    for i in range(8):
        for j in range(8):
            quad((g[i], 0, g[j]), (g[i], 0, g[j + 1]), (g[i + 1], 0, g[j + 1]), (g[i + 1], 0, g[j]))
    for _ in range(boxes):
        x, z = rng.uniform(-4, 4, 2)
        sx, sy, sz = rng.uniform(0.3, 1.2, 3)
        lo, hi = np.array([x - sx / 2, 0.0, z - sz / 2]), np.array([x + sx / 2, sy, z + sz / 2])
        c = [(lo[0] if i & 1 == 0 else hi[0], lo[1] if i & 2 == 0 else hi[1], lo[2] if i & 4 == 0 else hi[2]) for i in range(8)]
        for a, b, cc, d in [(0, 4, 6, 2), (1, 3, 7, 5), (0, 1, 5, 4), (2, 6, 7, 3), (0, 2, 3, 1), (4, 5, 7, 6)]:
            quad(c[a], c[b], c[cc], c[d])
    return np.asarray(vertices, np.float32), np.asarray(faces, np.uint32)


def ground_receivers(n, seed=2, y=0.0):
    """n points on the ground (a little above it is still "on" it: the engine offsets rays)."""
    rng = np.random.default_rng(seed)
    points = np.zeros((n, 3), np.float32)
    points[:, 0] = rng.uniform(-4.5, 4.5, n)
    points[:, 2] = rng.uniform(-4.5, 4.5, n)
    points[:, 1] = y
    normals = np.tile(np.float32([0, 1, 0]), (n, 1))
    # Some tilted normals, so that the frames differ from receiver to receiver.
    normals[::3, 0] = 0.3
    return points, normals


@pytest.fixture(scope="module")
def boxes():
    vertices, faces = boxes_scene()
    return vertices, faces, exao.Scene.from_arrays(vertices, faces)


def popcount_rows(masks):
    return np.unpackbits(masks.view(np.uint8), axis=1).sum(axis=1)


# --- Equality with the C++ API and exao query -----------------------------------------------


# The C++ API's default offset follows each point, the module's the scene's diagonal (as the
# exao program's): the equality tests give both this one.
OFFSET = 0.002


def api_masks(tmp_path, vertices, faces, points, normals, keys, samples, radius, falloff, backend):
    mesh, receivers, out = tmp_path / "mesh.bin", tmp_path / "receivers.bin", tmp_path / "masks.bin"
    mesh.write_bytes(struct.pack("<QQ", len(vertices), len(faces)) + vertices.tobytes() + faces.tobytes())
    receivers.write_bytes(struct.pack("<Q", len(points)) + points.tobytes() + normals.tobytes() + keys.astype(np.uint64).tobytes())
    subprocess.run([os.environ["EXAO_API_REFERENCE"], mesh, receivers, out, str(samples),
                    "default" if radius is None else repr(radius), falloff, backend, repr(OFFSET)], check=True)
    return np.fromfile(out, np.uint64).reshape(len(points), -1)


@pytest.mark.parametrize("samples,radius,falloff,method", [
    (128, None, "constant", "bvh"),
    (256, 1.5, "linear", "bvh"),
    (64, 0.75, "quadratic", "brute"),
    (96, 2.0, "constant", "embree"),
])
def test_masks_equal_the_cpp_api(tmp_path, boxes, samples, radius, falloff, method):
    vertices, faces, scene = boxes
    points, normals = ground_receivers(3000)
    keys = np.arange(len(points), dtype=np.uint64) * 7 + 3
    kwargs = dict(samples=samples, falloff=falloff, method=method, keys=keys, offset=OFFSET)
    if radius is not None:
        kwargs["radius"] = radius
    mine = scene.masks(points, normals, **kwargs)
    theirs = api_masks(tmp_path, vertices, faces, points, normals, keys, samples, radius, falloff, method)
    assert mine.dtype == np.uint64 and mine.shape == (len(points), (samples + 63) // 64)
    assert popcount_rows(mine).max() > 0, "the scene occludes nothing: the test would prove nothing"
    np.testing.assert_array_equal(mine, theirs)
    # ao() is 1 - blocked / N of the same masks, as a float32.
    ao = scene.ao(points, normals, **kwargs)
    assert ao.dtype == np.float32 and ao.shape == (len(points),)
    np.testing.assert_array_equal(ao, (1.0 - popcount_rows(mine).astype(np.float32) / np.float32(samples)).astype(np.float32))


def test_ao_equals_exao_query(tmp_path):
    room = exao.Scene.open("room")
    (lo, hi) = room.bounds
    rng = np.random.default_rng(5)
    n = 2000
    points = rng.uniform(lo, hi, (n, 3)).astype(np.float32)
    normals = rng.normal(size=(n, 3)).astype(np.float32)
    keys = np.arange(1, n + 1, dtype=np.uint64)
    lines = "".join(f"{p[0]!r} {p[1]!r} {p[2]!r} {m[0]!r} {m[1]!r} {m[2]!r} {k}\n"
                    for p, m, k in zip(points.tolist(), normals.tolist(), keys.tolist()))
    (tmp_path / "points.txt").write_text(lines)
    subprocess.run([os.environ["EXAO_BINARY"], "query", "room", "--points", tmp_path / "points.txt",
                    "-o", tmp_path / "ao.txt", "-n", "256", "-r", "3%"], check=True, capture_output=True)
    expected = np.loadtxt(tmp_path / "ao.txt", dtype=np.float32)
    got = room.ao(points, normals, keys=keys, samples=256, radius="3%")
    assert ((got > 0.0) & (got < 1.0)).any(), "no receiver is partly occluded: the test would prove nothing"
    np.testing.assert_array_equal(got, expected)


def test_bvh_and_brute_agree_through_the_method_string(boxes):
    _, _, scene = boxes
    points, normals = ground_receivers(500)
    np.testing.assert_array_equal(scene.masks(points, normals, method="bvh"), scene.masks(points, normals, method="brute"))


def test_default_method_is_the_engines(boxes):
    _, _, scene = boxes
    points, normals = ground_receivers(300)
    np.testing.assert_array_equal(scene.masks(points, normals), scene.masks(points, normals, method=exao.default_method()))


def test_non_contiguous_and_float64_input_give_the_same_answer(boxes):
    _, _, scene = boxes
    points, normals = ground_receivers(400)
    expected = scene.ao(points, normals)
    wide = np.zeros((400, 6), np.float32)
    wide[:, ::2] = points  # a strided view: every other column
    assert not wide[:, ::2].flags.c_contiguous
    np.testing.assert_array_equal(scene.ao(wide[:, ::2], np.asfortranarray(normals)), expected)
    np.testing.assert_array_equal(scene.ao(points.astype(np.float64), normals.astype(np.float64)), expected)


def test_from_arrays_reads_strided_vertices_and_int_faces():
    vertices, faces = boxes_scene(seed=3, boxes=4)
    a = exao.Scene.from_arrays(vertices, faces)
    padded = np.zeros((len(vertices), 4), np.float32)
    padded[:, :3] = vertices
    b = exao.Scene.from_arrays(padded[:, :3], faces.astype(np.int64))
    points, normals = ground_receivers(200)
    np.testing.assert_array_equal(a.masks(points, normals), b.masks(points, normals))


def test_one_sided_faces_block_only_from_the_front():
    # A floor-facing quad (front face down, toward the receivers) above a receiver, and the same
    # quad wound the other way: one-sided, only the first occludes.
    down = np.float32([[-1, 1, -1], [1, 1, -1], [1, 1, 1], [-1, 1, 1]])
    faces_front_down = np.uint32([[0, 1, 2], [0, 2, 3]])
    faces_front_up = faces_front_down[:, ::-1].copy()
    p, n = np.float32([[0, 0, 0]]), np.float32([[0, 1, 0]])
    blocked = exao.Scene.from_arrays(down, faces_front_down, two_sided=False).ao(p, n, radius=2.0)
    open_ = exao.Scene.from_arrays(down, faces_front_up, two_sided=False).ao(p, n, radius=2.0)
    both = exao.Scene.from_arrays(down, faces_front_up, two_sided=True).ao(p, n, radius=2.0)
    per_face = exao.Scene.from_arrays(down, faces_front_up, two_sided=np.array([1, 1], bool)).ao(p, n, radius=2.0)
    assert blocked[0] < 1.0 and open_[0] == 1.0 and both[0] == blocked[0] and per_face[0] == both[0]


def test_empty_points_give_an_empty_result(boxes):
    _, _, scene = boxes
    empty = np.zeros((0, 3), np.float32)
    assert scene.ao(empty, empty).shape == (0,)
    assert scene.masks(empty, empty, samples=256).shape == (0, 4)


def test_resolve_radius(boxes):
    _, _, scene = boxes
    (lo, hi) = scene.bounds
    diagonal = float(np.linalg.norm(np.float32(hi) - np.float32(lo)))
    assert scene.resolve_radius("10%") == pytest.approx(0.1 * diagonal, rel=1e-6)
    assert scene.resolve_radius(0.25) == 0.25


# --- Bad input --------------------------------------------------------------------------------


@pytest.mark.parametrize("vertices,faces,error,words", [
    (np.zeros((4, 3), np.int32), np.uint32([[0, 1, 2]]), TypeError, ["vertices", "int32"]),
    (np.zeros((4, 2), np.float32), np.uint32([[0, 1, 2]]), ValueError, ["vertices", "(n, 3)", "(4, 2)"]),
    (np.zeros(12, np.float32), np.uint32([[0, 1, 2]]), ValueError, ["vertices", "(12,)"]),
    ([[0, 0, 0]], np.uint32([[0, 1, 2]]), TypeError, ["vertices", "list"]),
    (np.eye(3, dtype=np.float32), np.float32([[0, 1, 2]]), TypeError, ["faces", "float32"]),
    (np.eye(3, dtype=np.float32), np.uint32([[0, 1]]), ValueError, ["faces", "(m, 3)"]),
    (np.eye(3, dtype=np.float32), np.zeros((0, 3), np.uint32), ValueError, ["faces", "empty"]),
    (np.eye(3, dtype=np.float32), np.uint32([[0, 1, 3]]), ValueError, ["faces[0]", "3", "out of range"]),
    (np.eye(3, dtype=np.float32), np.int32([[0, -1, 2]]), ValueError, ["faces[0]", "-1"]),
    (np.float32([[0, 0, 0], [1, np.nan, 0], [0, 0, 1]]), np.uint32([[0, 1, 2]]), ValueError, ["vertices[1]", "not finite"]),
    (np.float32([[0, 0, 0], [1, 0, 0], [2, 0, 0]]), np.uint32([[0, 1, 2]]), ValueError, ["zero area"]),
])
def test_bad_arrays_are_refused(vertices, faces, error, words):
    with pytest.raises(error) as raised:
        exao.Scene.from_arrays(vertices, faces)
    for word in words:
        assert word in str(raised.value)


def test_bad_two_sided_is_refused():
    with pytest.raises(ValueError, match="two_sided"):
        exao.Scene.from_arrays(np.eye(3, dtype=np.float32), np.uint32([[0, 1, 2]]), two_sided=np.ones(5, bool))
    with pytest.raises(TypeError, match="two_sided"):
        exao.Scene.from_arrays(np.eye(3, dtype=np.float32), np.uint32([[0, 1, 2]]), two_sided="yes")


@pytest.mark.parametrize("change,error,words", [
    (lambda p, n: (p.astype(np.int64), n), TypeError, ["points", "int64"]),
    (lambda p, n: (p[:, :2], n), ValueError, ["points", "(n, 3)"]),
    (lambda p, n: (p, n[:-1]), ValueError, ["normals", "rows"]),
    (lambda p, n: (np.where(np.arange(len(p))[:, None] == 7, np.nan, p).astype(np.float32), n), ValueError,
     ["receiver 7", "points[7]", "position is not finite"]),
    (lambda p, n: (p, np.where(np.arange(len(n))[:, None] == 4, 0.0, n).astype(np.float32)), ValueError,
     ["receiver 4", "normal has zero length"]),
    (lambda p, n: (p, np.where(np.arange(len(n))[:, None] == 2, np.inf, n).astype(np.float32)), ValueError,
     ["receiver 2", "normal is not finite"]),
])
def test_bad_receivers_are_refused(boxes, change, error, words):
    _, _, scene = boxes
    points, normals = change(*ground_receivers(10))
    with pytest.raises(error) as raised:
        scene.ao(points, normals)
    for word in words:
        assert word in str(raised.value)


@pytest.mark.parametrize("kwargs,words", [
    (dict(samples=100), ["samples", "multiple of 32", "100"]),
    (dict(samples=2048), ["samples", "2048"]),
    (dict(radius="x%"), ["radius", "x%"]),
    (dict(radius=-1.0), ["radius"]),
    (dict(falloff="cubic"), ["falloff", "cubic"]),
    (dict(method="nope"), ["method", "nope"]),
    (dict(method="raster"), ["method", "raster"]),
    (dict(masks="fuzzy"), ["masks", "fuzzy"]),
    (dict(sided="three"), ["sided", "three"]),
    (dict(threads=-1), ["threads"]),
    (dict(offset=float("nan")), ["offset"]),
    (dict(seed=-1), ["seed"]),
])
def test_bad_options_are_refused(boxes, kwargs, words):
    _, _, scene = boxes
    points, normals = ground_receivers(10)
    with pytest.raises(ValueError) as raised:
        scene.ao(points, normals, **kwargs)
    for word in words:
        assert word in str(raised.value)


def test_bad_keys_are_refused(boxes):
    _, _, scene = boxes
    points, normals = ground_receivers(10)
    with pytest.raises(ValueError, match="keys"):
        scene.ao(points, normals, keys=np.arange(9))
    with pytest.raises(TypeError, match="keys"):
        scene.ao(points, normals, keys=np.zeros(10, np.float32))


def test_bad_files_are_os_errors(tmp_path):
    with pytest.raises(FileNotFoundError) as raised:
        exao.Scene.open(tmp_path / "missing.obj")
    assert "missing.obj" in str(raised.value)
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nf 1 2 3 what\n")
    with pytest.raises(OSError) as raised:
        exao.Scene.open(bad)
    assert "bad.obj" in str(raised.value)


# --- The GIL, progress, cancelling -------------------------------------------------------------


@pytest.fixture(scope="module")
def long_job():
    """A query that takes seconds: many receivers at N = 1024 among the boxes."""
    vertices, faces = boxes_scene(seed=4, boxes=40)
    scene = exao.Scene.from_arrays(vertices, faces)
    points, normals = ground_receivers(150_000, seed=6)
    scene.ao(points[:10], normals[:10], samples=1024, radius="20%")  # build the engine first
    return scene, points, normals, dict(samples=1024, radius="20%")


def test_the_gil_is_released_while_the_engine_works(long_job):
    # Between the first progress call (done = 0, before the engine starts) and the last (done =
    # total, after it ends), this thread holds the GIL only while it calls progress: another
    # Python thread must count meanwhile. If the engine held the GIL, the count could not move.
    scene, points, normals, options = long_job
    counter = [0]
    stop = threading.Event()

    def count():
        while not stop.is_set():
            counter[0] += 1

    seen = []
    worker = threading.Thread(target=count)
    worker.start()
    try:
        scene.ao(points, normals, progress=lambda done, total: seen.append((done, total, counter[0])), **options)
    finally:
        stop.set()
        worker.join()
    assert seen[0][0] == 0 and seen[-1][0] == seen[-1][1] == len(points)
    assert seen[-1][2] > seen[0][2], "no other thread ran while the engine worked: the GIL was held"


def test_progress_is_called_on_the_calling_thread_in_order(long_job):
    scene, points, normals, options = long_job
    calls = []
    scene.ao(points, normals, progress=lambda done, total: calls.append((threading.get_ident(), done, total)), **options)
    assert {c[0] for c in calls} == {threading.get_ident()}
    assert all(total == len(points) for _, _, total in calls)
    dones = [done for _, done, _ in calls]
    assert dones == sorted(dones) and dones[0] == 0 and dones[-1] == len(points)


class Stop(Exception):
    pass


def test_raising_from_progress_cancels_the_job(long_job):
    scene, points, normals, options = long_job

    def progress(done, total):
        if 0 < done < total:
            raise Stop(f"stopped at {done} of {total}")

    with pytest.raises(Stop, match="stopped at"):
        scene.ao(points, normals, progress=progress, **options)
    job = exao._exao._last_job()
    assert job["cancelled"] and job["done"] < job["total"] == len(points), job
    # The scene still answers afterwards, and the same as ever.
    few = scene.ao(points[:50], normals[:50], **options)
    np.testing.assert_array_equal(few, scene.ao(points[:50], normals[:50], **options))


def test_a_progress_error_before_the_start_runs_nothing(boxes):
    _, _, scene = boxes
    points, normals = ground_receivers(100)

    def progress(done, total):
        raise Stop("no")

    with pytest.raises(Stop):
        scene.ao(points, normals, progress=progress)


def test_two_threads_query_one_scene_at_once(long_job):
    scene, points, normals, options = long_job
    subset = slice(0, 20_000)
    expected = scene.ao(points[subset], normals[subset], **options)
    results = [None, None]

    def run(i):
        results[i] = scene.ao(points[subset], normals[subset], **options)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r in results:
        np.testing.assert_array_equal(r, expected)


# --- exao.bake and exao.render -----------------------------------------------------------------


def test_bake_writes_a_glb_and_names_bad_options(tmp_path):
    out = tmp_path / "room.glb"
    calls = []
    assert exao.bake("room", out, samples=64, preview="", progress=lambda d, t: calls.append((d, t))) == out
    assert out.read_bytes()[:4] == b"glTF"
    with pytest.raises(ValueError) as raised:
        exao.bake("room", tmp_path / "x.glb", samples=100)
    assert "samples" in str(raised.value) and "100" in str(raised.value)
    with pytest.raises(ValueError) as raised:
        exao.bake("room", tmp_path / "x.glb", no_such_option=3)
    assert "no-such-option" in str(raised.value) or "no_such_option" in str(raised.value)
    with pytest.raises(OSError) as raised:
        exao.bake(tmp_path / "missing.glb", tmp_path / "x.glb")
    assert "missing.glb" in str(raised.value)
    assert not (tmp_path / "x.glb").exists()


def test_bake_texture_takes_the_programs_flags(tmp_path):
    out = tmp_path / "room-tex.glb"
    exao.bake("room", out, texture=256, texel_samples=1, margin=1, samples=32, preview="", ground=True)
    assert out.read_bytes()[:4] == b"glTF"
    assert any(p.suffix == ".png" for p in tmp_path.iterdir()), "the AO map beside the output"


def test_render_writes_exr_and_png_and_can_be_cancelled(tmp_path):
    exr, png = tmp_path / "ao.exr", tmp_path / "ao.png"
    assert exao.render("room", exr, png=png, width=64, height=48, samples=32) == exr
    assert exr.exists() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    def progress(done, total):
        if 0 < done < total:
            raise Stop("cancel")

    big = tmp_path / "big.exr"
    with pytest.raises(Stop):
        exao.render("room", big, png="", width=1600, height=1200, samples=1024, method="embree", progress=progress)
    assert not big.exists()
    assert not [p for p in tmp_path.iterdir() if "partial" in p.name]
