"""The Python module against the C++ app on the bundled meshes, and its handling of bad arrays,
options and files, the GIL and Ctrl-C. Run by ctest (Python.Pytest), which sets PYTHONPATH to
the built module, VISIMP_APP to the `visimp` executable and VISIMP_MESHES_DIR to meshes/."""

import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import visimp

APP = os.environ.get("VISIMP_APP", "visimp")
MESHES = os.environ.get("VISIMP_MESHES_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "meshes"))
# Reduced sampling: the numbers are compared with the app at the same settings, not with the paper.
QUICK = dict(cameras=18, resolution=128, threads=1)
QUICK_FLAGS = ["--cameras", "18", "--resolution", "128", "--threads", "1"]


def mesh_path(name):
    return os.path.join(MESHES, name)


def app(*args):
    done = subprocess.run([APP, *args], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


@pytest.fixture(scope="module")
def bunny():
    return visimp.read_mesh(mesh_path("bunny.ply"))


# --- read_mesh / write_mesh -------------------------------------------------------------------

@pytest.mark.parametrize("name", ["bunny.ply", "fandisk_cad.ply", "teapot.ply", "aneurysm_open.ply"])
@pytest.mark.parametrize("ext", ["ply", "obj", "off"])
def test_round_trip_is_exact(tmp_path, name, ext):
    V, F = visimp.read_mesh(mesh_path(name))
    assert V.dtype == np.float64 and V.shape[1] == 3 and F.dtype == np.int64 and F.shape[1] == 3
    out = str(tmp_path / f"copy.{ext}")
    visimp.write_mesh(out, V, F)
    V2, F2 = visimp.read_mesh(out)
    np.testing.assert_array_equal(F2, F)
    # PLY keeps the stored precision; OBJ and OFF print 17 significant digits.
    np.testing.assert_array_equal(V2, V)


def test_read_mesh_matches_the_app_counts(bunny):
    V, F = bunny
    info = json.loads(app("info", mesh_path("bunny.ply"), "--json"))
    assert (len(V), len(F)) == (info["vertices"], info["faces"])


ASSIMP_MODELS = "/usr/share/assimp/models"


@pytest.mark.skipif(not os.path.isdir(ASSIMP_MODELS), reason="assimp-testmodels is not installed")
def test_scene_formats_read_and_refuse_to_be_written(tmp_path):
    V, F = visimp.read_mesh(os.path.join(ASSIMP_MODELS, "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb"))
    assert V.shape == (8, 3) and F.shape == (12, 3)  # welded, as the app reads it
    with pytest.raises(OSError, match="dropped"):
        visimp.read_mesh(os.path.join(ASSIMP_MODELS, "glTF2/IndexOutOfRange/IndexOutOfRange.gltf"))
    with pytest.raises(ValueError, match="does not write"):
        visimp.write_mesh(str(tmp_path / "box.glb"), V, F)
    assert not (tmp_path / "box.glb").exists()


def test_face_quality_round_trips_through_ply(tmp_path, bunny):
    V, F = bunny
    q = np.linspace(0, 1, len(F), dtype=np.float32)
    out = str(tmp_path / "q.ply")
    visimp.write_mesh(out, V, F, face_quality=q)
    _, _, q2 = visimp.read_mesh(out, face_quality=True)
    np.testing.assert_array_equal(q2, q)
    assert visimp.read_mesh(mesh_path("bunny.ply"), face_quality=True)[2] is None


def test_lists_and_other_dtypes_are_accepted(tmp_path):
    V = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    out = str(tmp_path / "tri.ply")
    visimp.write_mesh(out, np.asarray(V, dtype=np.float32), np.asarray([[0, 1, 2]], dtype=np.uint8))
    V2, F2 = visimp.read_mesh(out)
    np.testing.assert_array_equal(V2, np.asarray(V, dtype=np.float64))
    np.testing.assert_array_equal(F2, [[0, 1, 2]])


# --- results equal the C++ app's, bit for bit -------------------------------------------------

@pytest.mark.parametrize("name", ["bunny.ply", "fandisk_cad.ply", "aneurysm_open.ply"])
def test_visibility_equals_the_app(tmp_path, name):
    V, F = visimp.read_mesh(mesh_path(name))
    r = visimp.visibility(V, F, **QUICK)
    out = str(tmp_path / "v.ply")
    summary = json.loads(app("visibility", mesh_path(name), out, "--json", *QUICK_FLAGS))
    _, _, q = visimp.read_mesh(out, face_quality=True)
    np.testing.assert_array_equal(r["face"], q)
    assert r["face"].dtype == np.float32 and r["face"].shape == (len(F),)
    assert r["mesh"] == pytest.approx(summary["mesh_visibility"], abs=1e-9)
    assert r["stats"]["cameras"] == 18 and r["stats"]["resolution"] == 128
    assert 0 <= r["mesh"] <= 1


def test_visibility_of_a_convex_mesh_is_one_whatever_the_winding():
    # An octahedron: convex, so every face is seen from every camera in front of it.
    V = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=float)
    F = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    for faces in (F, F[:, ::-1]):
        r = visimp.visibility(V, np.ascontiguousarray(faces), **QUICK)
        np.testing.assert_allclose(r["face"], 1.0)
        assert r["mesh"] == pytest.approx(1.0)


@pytest.mark.parametrize("method", ["qb", "vg"])
def test_simplify_equals_the_app(tmp_path, method):
    V, F = visimp.read_mesh(mesh_path("bunny.ply"))
    V2, F2, result = visimp.simplify(V, F, target=0.1, method=method, **QUICK)
    out = str(tmp_path / "s.ply")
    app("simplify", mesh_path("bunny.ply"), out, "--ratio", "0.1", "--method", method, *QUICK_FLAGS)
    V3, F3 = visimp.read_mesh(out)
    np.testing.assert_array_equal(F2, F3)
    # The app's PLY stores float coordinates when that moves none by more than 1e-7 of the diagonal.
    np.testing.assert_array_equal(V2.astype(np.float32).astype(np.float64), V3)
    assert result["faces_out"] == len(F2) <= len(F) // 10 + 1
    assert result["stop_reason"] == "target_reached"


def test_quadric_weights_equal_the_app(tmp_path):
    V, F = visimp.read_mesh(mesh_path("teapot.ply"))
    out = str(tmp_path / "s.ply")
    app("simplify", mesh_path("teapot.ply"), out, "--ratio", "0.1", "--quadric-weights", "uniform")
    _, F_app = visimp.read_mesh(out)
    _, F_uniform, _ = visimp.simplify(V, F, target=0.1, quadric_weights="uniform")
    _, F_area, _ = visimp.simplify(V, F, target=0.1)  # area is the default
    np.testing.assert_array_equal(F_uniform, F_app)
    assert F_uniform.shape == F_area.shape and not np.array_equal(F_uniform, F_area)
    with pytest.raises(ValueError, match="quadric_weights must be 'uniform' or 'area'"):
        visimp.simplify(V, F, target=0.1, quadric_weights="none")


def test_area_floor_equals_the_app(tmp_path):
    V, F = visimp.read_mesh(mesh_path("teapot.ply"))
    out = str(tmp_path / "s.ply")
    app("simplify", mesh_path("teapot.ply"), out, "--ratio", "0.1", "--area-floor", "1")
    _, F_app = visimp.read_mesh(out)
    _, F_floor, _ = visimp.simplify(V, F, target=0.1, area_floor=1.0)
    _, F_area, _ = visimp.simplify(V, F, target=0.1)  # no floor by default
    np.testing.assert_array_equal(F_floor, F_app)
    assert not np.array_equal(F_floor, F_area)
    with pytest.raises(ValueError, match="area_floor must be a finite number >= 0"):
        visimp.simplify(V, F, target=0.1, area_floor=-1.0)
    with pytest.raises(ValueError, match="area_floor applies to area weights only"):
        visimp.simplify(V, F, target=0.1, area_floor=1.0, quadric_weights="uniform")


def test_vg_with_given_visibility_equals_vg_that_measures_it(bunny):
    V, F = bunny
    vis = visimp.visibility(V, F, **QUICK)["face"]
    a = visimp.simplify(V, F, target=500, method="vg", visibility=vis)
    b = visimp.simplify(V, F, target=500, method="vg", **QUICK)
    np.testing.assert_array_equal(a[1], b[1])
    # V = 1 everywhere is QB, bit for bit (simplify.h).
    c = visimp.simplify(V, F, target=500, method="vg", visibility=np.ones(len(F)))
    d = visimp.simplify(V, F, target=500, method="qb")
    np.testing.assert_array_equal(c[0], d[0])
    np.testing.assert_array_equal(c[1], d[1])


def test_levels_equal_single_runs(bunny):
    V, F = bunny
    levels = visimp.simplify(V, F, levels=[1000, 300])
    assert [len(l[1]) for l in levels] == [1000, 300]
    for (Vl, Fl, rl), target in zip(levels, [1000, 300]):
        Vs, Fs, rs = visimp.simplify(V, F, target=target, serial_collapses=True)
        assert rs["parallel_collapses"] == 0
        np.testing.assert_array_equal(Fl, Fs)
        np.testing.assert_array_equal(Vl, Vs)
    assert len(visimp.simplify(V, F, target=0.05, levels=3)) == 3


def test_serial_collapses_keeps_the_parallel_phase_out():
    # A bumpy 300 x 300 grid: 90,000 vertices, enough for the phase's two partitions.
    n = 300
    xs, ys = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    V = np.stack([xs.ravel(), ys.ravel(), (0.05 * np.sin(9 * xs) * np.sin(7 * ys + 1)).ravel()], axis=1)
    v = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]).ravel()
    F = np.concatenate([np.stack([v, v + 1, v + n], 1), np.stack([v + 1, v + n + 1, v + n], 1)]).astype(np.int64)
    _, _, phased = visimp.simplify(V, F, target=9000)
    _, Fs, serial = visimp.simplify(V, F, target=9000, serial_collapses=True)
    assert phased["parallel_collapses"] > 0
    assert serial["parallel_collapses"] == 0
    # Edges costed after the set-up, the phase's lanes included: at least one new edge per
    # collapse on a grid, and fewer than eagerly (every edge at the merged vertex, ~6).
    for r in (phased, serial):
        assert r["collapses"] < r["requeued_edges"] < 5 * r["collapses"]
    np.testing.assert_array_equal(visimp.simplify(V, F, levels=[9000])[0][1], Fs)


def test_metro_equals_the_app(tmp_path, bunny):
    V, F = bunny
    V2, F2, _ = visimp.simplify(V, F, target=0.1)
    out = str(tmp_path / "s.ply")
    visimp.write_mesh(out, V2, F2)
    Vr, Fr = visimp.read_mesh(out)  # what the app reads
    d = visimp.metro((V, F), (Vr, Fr), samples=20000, threads=1)
    ref = json.loads(app("metro", mesh_path("bunny.ply"), out, "--json", "--samples", "20000", "--threads", "1"))
    for key in ("max", "mean", "rms", "samples"):
        assert d["a_to_b"][key] == pytest.approx(ref["a_to_b"][key], rel=1e-9)
        assert d["b_to_a"][key] == pytest.approx(ref["b_to_a"][key], rel=1e-9)
    assert d["diagonal"] == pytest.approx(ref["diagonal"], rel=1e-9)
    assert d["hausdorff"] == max(d["a_to_b"]["max"], d["b_to_a"]["max"])
    assert d["a_to_b"]["histogram_area_share"].sum() == pytest.approx(1.0)
    assert visimp.metro((V, F), (V, F), samples=5000)["hausdorff_relative"] < 1e-12


def test_image_error_equals_the_app(tmp_path, bunny):
    V, F = bunny
    V2, F2, _ = visimp.simplify(V, F, target=0.1)
    out = str(tmp_path / "s.ply")
    visimp.write_mesh(out, V2, F2)
    Vr, Fr = visimp.read_mesh(out)
    e = visimp.image_error((V, F), (Vr, Fr), resolution=64, threads=1)
    ref = json.loads(app("imgerr", mesh_path("bunny.ply"), out, "--json", "--resolution", "64", "--threads", "1"))
    assert e["rms"] == pytest.approx(ref["rms"], rel=1e-9)
    np.testing.assert_allclose(e["view_rms_per_pixel"], ref["view_rms_per_pixel"], rtol=1e-9)
    assert e["views"] == 20
    assert visimp.image_error((V, F), (V, F), resolution=32)["rms"] == 0


def test_references_measure_many_results_as_one_call_each(bunny):
    V, F = bunny
    levels = [visimp.simplify(V, F, target=t)[:2] for t in (0.3, 0.05)]
    vis = np.linspace(0.0, 1.0, len(F))
    metro = visimp.MetroReference((V, F), samples=20000, threads=1, visibility=vis)
    image = visimp.ImageErrorReference((V, F), resolution=64, threads=1)
    for B in levels:
        d = metro.distance_to(B)
        one = visimp.metro((V, F), B, samples=20000, threads=1, visibility=vis)
        for key in ("hausdorff", "rms", "diagonal"):
            assert d[key] == one[key]
        for side in ("a_to_b", "b_to_a"):
            np.testing.assert_array_equal(d[side]["histogram_area_share"], one[side]["histogram_area_share"])
        assert d["visible"] == one["visible"]
        e = image.error_to(B)
        assert e["rms"] == visimp.image_error((V, F), B, resolution=64, threads=1)["rms"]
    assert metro.distance_to(levels[0])["hausdorff"] != metro.distance_to(levels[1])["hausdorff"]
    with pytest.raises(ValueError):
        visimp.ImageErrorReference((V, F), supersample=9)
    with pytest.raises(ValueError):
        metro.distance_to(V)  # not a (V, F) pair


def test_compare_writes_the_report(tmp_path):
    out = tmp_path / "cmp"
    r = visimp.compare(mesh_path("teapot.ply"), str(out), levels=2, cameras=18, resolution=96,
                       image_resolution=64, metro_samples=2000)
    assert len(r["targets"]) == 2 and len(r["qb"]) == 2 and len(r["vg"]) == 2
    for level, target in zip(r["vg"], r["targets"]):
        assert level["faces"] <= target and level["image"]["rms"] >= 0 and level["metro"]["hausdorff"] >= 0
    assert (out / "results.json").exists() and (out / "report.html").exists()
    saved = json.loads((out / "results.json").read_text())
    assert [level["target"] for level in saved["per_level"]] == r["targets"]  # the run returned
    # ...and what it was made with, under the app's flag names, as `visimp compare` records it
    options = saved["options"]
    assert (options["levels"], options["cameras"], options["resolution"], options["image_resolution"],
            options["metro_samples"], options["backend"], options["targets"]) == (2, "18", 96, 64, 2000, "raster", "")
    assert "threads" not in options and "ratio" not in options  # no result depends on them
    assert options["quadric_weights"] == saved["quadric_weights"]
    assert all(os.path.exists(f) for f in r["files"])


# --- bad input: clear errors, by kind --------------------------------------------------------

@pytest.mark.parametrize("V_bad, message", [
    (lambda V: V.astype(np.int32), "V must have a floating-point dtype"),
    (lambda V: V[:, :2], r"V must have shape \(n, 3\), got \(\d+, 2\)"),
    (lambda V: V.ravel(), r"V must have shape \(n, 3\)"),
    (lambda V: np.where(np.arange(len(V))[:, None] == 4, np.nan, V), r"V\[4\] is not finite"),
    (lambda V: V.astype(str), "V must have a floating-point dtype"),
])
def test_bad_vertices_are_value_errors(bunny, V_bad, message):
    V, F = bunny
    with pytest.raises(ValueError, match=message):
        visimp.simplify(V_bad(V), F, target=100)


@pytest.mark.parametrize("F_bad, message", [
    (lambda F, n: F.astype(np.float64), "F must have an integer dtype"),
    (lambda F, n: F[:, :2], r"F must have shape \(n, 3\)"),
    (lambda F, n: np.vstack([F, [[0, 1, n]]]), r"F\[3674, 2\] = 1839 is not a vertex index \(V has 1839 rows\)"),
    (lambda F, n: np.vstack([F, [[0, -1, 2]]]), r"F\[3674, 1\] = -1 is not a vertex index"),
])
def test_bad_faces_are_value_errors(bunny, F_bad, message):
    V, F = bunny
    with pytest.raises(ValueError, match=message):
        visimp.visibility(V, F_bad(F, len(V)), **QUICK)


def test_bad_options_name_the_keyword(bunny):
    V, F = bunny
    with pytest.raises(ValueError, match="resolution must be in 16..8192"):
        visimp.visibility(V, F, resolution=3)
    with pytest.raises(ValueError, match="method must be 'qb' or 'vg'"):
        visimp.simplify(V, F, target=10, method="fast")
    with pytest.raises(ValueError, match="target"):
        visimp.simplify(V, F, target=1.5)
    with pytest.raises(ValueError, match="target"):
        visimp.simplify(V, F, target=0)
    with pytest.raises(ValueError, match="not a bool"):
        visimp.simplify(V, F, target=True)
    with pytest.raises(ValueError, match="max_normal_change_deg"):
        visimp.simplify(V, F, target=10, max_normal_change_deg=0)
    with pytest.raises(ValueError, match="cameras"):
        visimp.visibility(V, F, cameras=[1, 2])
    with pytest.raises(ValueError, match="visibility must have one value per face"):
        visimp.simplify(V, F, target=10, method="vg", visibility=np.ones(10))
    with pytest.raises(ValueError, match=r"visibility\[0\] = 2"):
        visimp.simplify(V, F, target=10, method="vg", visibility=np.full(len(F), 2.0))
    with pytest.raises(ValueError, match="only used by method='vg'"):
        visimp.simplify(V, F, target=10, visibility=np.ones(len(F)))
    with pytest.raises(ValueError, match=r"A must be a \(V, F\) pair"):
        visimp.metro(V, (V, F))
    with pytest.raises(TypeError):  # options are keyword-only
        visimp.visibility(V, F, 18)


def test_io_failures_are_os_errors(tmp_path, bunny):
    V, F = bunny
    with pytest.raises(OSError, match="no_such.ply"):
        visimp.read_mesh(str(tmp_path / "no_such.ply"))
    bad = tmp_path / "bad.ply"
    bad.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n")
    with pytest.raises(OSError, match="bad.ply"):
        visimp.read_mesh(str(bad))
    with pytest.raises(OSError, match="missing_dir"):
        visimp.write_mesh(str(tmp_path / "missing_dir" / "out.ply"), V, F)


# --- the GIL and Ctrl-C ------------------------------------------------------------------------

def test_long_calls_release_the_gil(bunny):
    V, F = bunny
    done = threading.Event()

    def work():
        visimp.visibility(V, F, cameras=258, resolution=256, threads=1)
        done.set()

    ticks = 0
    worker = threading.Thread(target=work)
    worker.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    # Holding the GIL for the whole call would leave this thread no turn until it returned.
    assert ticks > 20


def test_ctrl_c_interrupts_a_long_call(tmp_path):
    script = tmp_path / "long.py"
    script.write_text(
        "import sys, visimp\n"
        f"V, F = visimp.read_mesh({mesh_path('bunny.ply')!r})\n"
        "print('started', flush=True)\n"
        "visimp.visibility(V, F, cameras=4098, resolution=1024, threads=1)\n"
        "print('finished', flush=True)\n")
    child = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, env=os.environ.copy())
    assert child.stdout.readline().strip() == "started"
    time.sleep(1.0)
    child.send_signal(signal.SIGINT)
    try:
        out, err = child.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        child.kill()
        pytest.fail("visibility did not stop on SIGINT")
    assert "KeyboardInterrupt" in err
    assert "finished" not in out
    assert child.returncode != 0
