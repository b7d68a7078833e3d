"""The Python module (import facetool) against independent references: numpy's own sRGB decoding
and similarity transform, the renderer's identity reconstruction = albedo x shading, the facetool
program's faces.json and photo.exr of the same photo, light-format round trips, the identity
relighting; bad arrays raise clear Python exceptions; the GIL is released during compute."""

import json
import os
import subprocess
import tempfile
import threading

import numpy as np
import pytest

import facetool

EXAMPLES = os.environ.get("FACETOOL_EXAMPLES_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "examples"))
PHOTO = os.path.join(EXAMPLES, "photos", "astronaut.png")
LANDMARKS = "/usr/share/dlib/shape_predictor_68_face_landmarks.dat"

needs_photo_model = pytest.mark.skipif(
    not os.path.exists(LANDMARKS) or not os.path.exists(PHOTO),
    reason="dlib's landmark model (libdlib-data) or examples/photos/astronaut.png is missing")


def srgb_to_linear(v):
    v = v.astype(np.float64) / 255.0
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


@pytest.fixture(scope="module")
def model():
    try:
        return facetool.load_model()
    except facetool.Error as e:
        pytest.skip(f"no shipped model: {e}")


@pytest.fixture(scope="module")
def photo(model):
    if not os.path.exists(LANDMARKS) or not os.path.exists(PHOTO):
        pytest.skip("dlib's landmark model or the example photo is missing")
    return model.decompose_file(PHOTO)


def test_backends_and_model(model):
    assert "cpu" in facetool.backends()
    assert model.backend == "cpu"
    assert model.input_size > 0
    assert model.weights.endswith(".safetensors")
    with pytest.raises(facetool.Error, match="no-such-weights"):
        facetool.load_model("no-such-weights.safetensors")
    with pytest.raises(facetool.Error):
        facetool.load_model(backend="no-such-backend")


@needs_photo_model
def test_shapes_and_layouts(photo, model):
    s = model.input_size
    h, w = photo.image.shape[:2]
    assert len(photo.faces) >= 1 and len(photo) == len(photo.faces)
    for f in photo.faces:
        assert f.crop.shape == (s, s, 3) and f.albedo.shape == (s, s, 3) and f.normal.shape == (s, s, 3)
        assert f.visibility.shape == (s, s, 9) and f.mask.shape == (s, s)
        assert f.light.shape == (3, 9) and f.light_photo.shape == (3, 9)
        assert f.landmarks.shape == (68, 2) and f.coverage.shape == (h, w)
        assert f.albedo.dtype == np.float32
        # the renderer's image is albedo x shading: checks the channel order of three arrays
        np.testing.assert_allclose(f.reconstruction, f.albedo * f.shading, rtol=1e-4, atol=1e-5)
        # unit normals inside the mask
        lengths = np.linalg.norm(f.normal[f.mask > 0.5], axis=1)
        np.testing.assert_allclose(lengths, 1.0, atol=1e-3)
        # landmarks_crop is photo_to_crop applied to the photo landmarks (numpy's own product)
        t = f.photo_to_crop
        mapped = f.landmarks @ t[:, :2].T + t[:, 2]
        np.testing.assert_allclose(f.landmarks_crop, mapped, atol=1e-9)
        assert (f.coverage >= 0).all() and (f.coverage <= 1).all()
    for name, c in [("alpha", None), ("albedo", 3), ("normal", 3), ("visibility", 9), ("shading", 3),
                    ("reconstruction", 3)]:
        a = getattr(photo, name)
        assert a.shape == ((h, w) if c is None else (h, w, c)), name
    # one face: its coverage is the photo's alpha
    if len(photo.faces) == 1:
        np.testing.assert_allclose(photo.faces[0].coverage, photo.alpha, atol=1e-6)


@needs_photo_model
def test_same_as_the_facetool_program(photo):
    exe = os.environ.get("FACETOOL_EXE")
    if not exe:
        pytest.skip("FACETOOL_EXE not set (run through ctest)")
    with tempfile.TemporaryDirectory() as out:
        subprocess.run([exe, "infer", PHOTO, "-o", out, "--no-contact-sheet"], check=True,
                       capture_output=True)
        faces = json.load(open(os.path.join(out, "astronaut", "faces.json")))["faces"]
        assert len(faces) == len(photo.faces)
        for f, j in zip(photo.faces, faces):
            np.testing.assert_allclose(f.landmarks, np.array(j["landmarks"]), atol=1e-6)
            np.testing.assert_allclose(f.light_photo.reshape(27), np.array(j["light_photo_frame"]), rtol=1e-6,
                                       atol=1e-7)
            np.testing.assert_allclose(f.photo_to_crop, np.array(j["photo_to_crop"]), rtol=1e-6, atol=1e-6)
        # the crop-level light file of face 0
        path = os.path.join(out, "astronaut", "face_0", "light.json")
        c = json.load(open(path))["coefficients"]
        values = np.array([c["r"], c["g"], c["b"]])
        np.testing.assert_allclose(photo.faces[0].light, values, rtol=1e-6, atol=1e-6)
        np.testing.assert_allclose(facetool.read_light(path), values, rtol=1e-12)


@needs_photo_model
def test_mirror_average_answers_the_mirrored_photo_with_the_mirrored_answer(photo, model):
    """The default (mirror_average=True) decomposes the photo seen in a mirror into the mirror of
    its decomposition (crop-level normals and albedo, the normal's x negated), up to the landmarks'
    and the resampling's rounding; one pass per face (mirror_average=False) does not, and differs
    from the default on the photo itself. The network's answers alone: the landmark normal head
    reads the mirrored face's landmarks, which the average does not make symmetric."""
    network = facetool.load_model(landmark_normals=False)
    photo = network.decompose(photo.image)
    model = network
    single = facetool.load_model(mirror_average=False, landmark_normals=False)
    mirror_image = np.ascontiguousarray(photo.image[:, ::-1])

    def mirror_difference(m, original):
        face, seen = original.faces[0], m.decompose(mirror_image).faces[0]
        back = seen.normal[:, ::-1] * np.array([-1.0, 1.0, 1.0], dtype=np.float32)
        inside = (face.mask > 0.5) & (seen.mask[:, ::-1] > 0.5)
        return (np.abs(back - face.normal)[inside].mean(), np.abs(seen.albedo[:, ::-1] - face.albedo)[inside].mean())

    own = single.decompose(photo.image)
    assert np.abs(own.faces[0].normal - photo.faces[0].normal).mean() > 1e-3
    averaged, plain = mirror_difference(model, photo), mirror_difference(single, own)
    print("mean |difference| to the mirrored answer (normal, albedo): default", averaged, "one pass", plain)
    assert averaged[0] < 0.5 * plain[0] and averaged[1] < 0.5 * plain[1]


@needs_photo_model
def test_the_landmark_normal_head_changes_the_normals_only(photo):
    """The shipped weights carry a landmark normal head: the default blends its normals into the
    network's (docs/model-card.md); landmark_normals=False gives the network's alone. The albedo
    and the light come from the network either way (the light's gain and solve, which need the
    head's face mask, left out on both sides)."""
    head = facetool.load_model(light_gain=False, light_solve=False).decompose(photo.image)
    alone = facetool.load_model(landmark_normals=False).decompose(photo.image)
    a, b = head.faces[0], alone.faces[0]
    inside = a.mask > 0.5
    assert np.degrees(np.arccos(np.clip((a.normal * b.normal).sum(-1), -1, 1)))[inside].mean() > 2.0
    np.testing.assert_array_equal(a.albedo, b.albedo)
    np.testing.assert_array_equal(a.light, b.light)


def test_the_lights_gain_scales_each_colour_of_the_light(photo):
    """The default scales each colour of the network's light to render the face best
    (docs/photos.md, "The light's gain"); light_gain=False keeps the network's: the two lights
    differ by one factor per colour, the shading by the same factors, the albedo and normals not."""
    plain = facetool.load_model(light_gain=False, light_solve=False).decompose(photo.image).faces[0]
    gained = facetool.load_model(light_solve=False).decompose(photo.image).faces[0]
    gain = gained.light[:, 0] / plain.light[:, 0]
    assert np.abs(gain - 1).max() > 1e-3
    np.testing.assert_allclose(gained.light, plain.light * gain[:, None], rtol=1e-5, atol=1e-7)
    np.testing.assert_allclose(gained.shading, plain.shading * gain[None, None, :], rtol=1e-5, atol=1e-6)
    np.testing.assert_array_equal(gained.albedo, plain.albedo)
    np.testing.assert_array_equal(gained.normal, plain.normal)


@needs_photo_model
def test_the_light_solve_replaces_the_light_and_the_albedo_follows(photo):
    """The default solves each face's light from its shading (docs/photos.md, "The light from the
    shading"): a distant light plus ambient, so the light differs from the network's; the normals
    stay; the albedo follows from the photo and the new shading, and the reconstruction is albedo
    times shading."""
    network = facetool.load_model(light_solve=False).decompose(photo.image).faces[0]
    solved = photo.faces[0]
    np.testing.assert_array_equal(solved.normal, network.normal)
    assert np.abs(solved.light - network.light).max() > 1e-3
    assert np.abs(solved.albedo - network.albedo).max() > 1e-2
    np.testing.assert_allclose(solved.reconstruction, solved.albedo * solved.shading, rtol=1e-5, atol=1e-6)
    assert np.isfinite(solved.light).all()


def test_light_from_direction_shades_ambient_plus_the_cosine():
    """facetool.light_from_direction: a white distant light; facing it, with nothing occluded, the
    shading is ambient + 1.0625 x intensity (the 9 coefficients' cosine), as `light from-direction`."""
    light = facetool.light_from_direction(30.0, 10.0, ambient=0.2, intensity=1.5)
    assert light.shape == (3, 9)
    a, e = np.radians(30.0), np.radians(10.0)
    d = np.array([np.sin(a) * np.cos(e), np.sin(e), np.cos(a) * np.cos(e)])
    y = np.array([0.282095, 0.488603 * d[1], 0.488603 * d[2], 0.488603 * d[0], 1.092548 * d[0] * d[1],
                  1.092548 * d[1] * d[2], 0.315392 * (3 * d[2] ** 2 - 1), 1.092548 * d[0] * d[2],
                  0.546274 * (d[0] ** 2 - d[1] ** 2)])
    band = np.array([np.pi] + [2 * np.pi / 3] * 3 + [np.pi / 4] * 5)
    shading = (light * band * y).sum(-1) / np.pi
    np.testing.assert_allclose(shading, 0.2 + 1.5 * 1.0625, rtol=1e-5)
    with pytest.raises(ValueError):
        facetool.light_from_direction(float("nan"), 0.0)


@needs_photo_model
def test_uint8_is_decoded_from_srgb(model):
    rgb8 = (np.clip(facetool.read_image(PHOTO), 0, 1) ** (1 / 2.2) * 255).round().astype(np.uint8)
    a = model.decompose(rgb8)
    b = model.decompose(srgb_to_linear(rgb8).astype(np.float32))
    np.testing.assert_allclose(a.image, b.image, atol=1e-6)
    np.testing.assert_allclose(a.faces[0].light, b.faces[0].light, atol=1e-5)


@needs_photo_model
def test_any_strides_and_float64(model):
    image = facetool.read_image(PHOTO)
    flipped = image[:, ::-1]  # a negative-stride view
    a = model.decompose(flipped)
    b = model.decompose(np.ascontiguousarray(flipped).astype(np.float64))
    np.testing.assert_allclose(a.faces[0].albedo, b.faces[0].albedo, atol=1e-6)
    np.testing.assert_array_equal(a.image, np.ascontiguousarray(flipped))


@needs_photo_model
def test_relight_with_own_light_returns_the_photo(photo, model):
    if len(photo.faces) != 1:
        pytest.skip("the identity transfer needs a photo with one face")
    relit = facetool.relight(photo, photo.faces[0].light_photo, model=model)
    assert relit.shape == photo.image.shape
    np.testing.assert_allclose(relit, photo.image, atol=2e-3)
    turned = model.relight(photo, facetool.light_from_dpr([0.8, 0, 0, 0.5, 0, 0, 0, 0, 0]))
    assert np.abs(turned - photo.image).max() > 0.02


def test_light_conversions_round_trip():
    rng = np.random.default_rng(1)
    v = rng.normal(size=27)
    np.testing.assert_allclose(facetool.light_to_sfsnet(facetool.light_from_sfsnet(v)), v, atol=1e-12)
    g = rng.normal(size=9)
    np.testing.assert_allclose(facetool.light_to_dpr(facetool.light_from_dpr(g)), g, atol=1e-12)
    grey = facetool.light_from_dpr(g)
    np.testing.assert_allclose(grey[0], grey[1])  # grey: equal rows
    np.testing.assert_allclose(grey[1], grey[2])


def test_bad_arrays_raise_clear_exceptions(model):
    with pytest.raises(TypeError, match="numpy array"):
        model.decompose([[1, 2, 3]])
    with pytest.raises(TypeError, match="dtype"):
        model.decompose(np.zeros((8, 8, 3), dtype=np.int64))
    with pytest.raises(TypeError, match="dtype"):
        model.decompose(np.zeros((8, 8, 3), dtype=bool))
    with pytest.raises(ValueError, match="channels first"):
        model.decompose(np.zeros((3, 64, 64), dtype=np.float32))
    with pytest.raises(ValueError, match=r"\(height, width, 3\)"):
        model.decompose(np.zeros((64, 64), dtype=np.float32))
    with pytest.raises(ValueError, match=r"\(height, width, 3\)"):
        model.decompose(np.zeros((64, 64, 4), dtype=np.uint8))
    with pytest.raises(ValueError, match="pixels"):
        model.decompose(np.zeros((0, 5, 3), dtype=np.float32))
    nan = np.zeros((16, 16, 3), dtype=np.float32)
    nan[3, 4, 1] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        model.decompose(nan)
    with pytest.raises(ValueError, match="max_faces"):
        model.decompose(np.zeros((16, 16, 3), dtype=np.float32), max_faces=-1)
    with pytest.raises(ValueError, match="SfSNet"):
        facetool.light_from_sfsnet(np.zeros(26))
    with pytest.raises(ValueError, match=r"\(3, 9\)"):
        facetool.light_to_dpr(np.zeros((9, 3)))
    for size in (float("inf"), float("nan"), -1.0, 2e6):
        with pytest.raises(ValueError, match="min_face_size"):
            model.decompose(np.zeros((16, 16, 3), dtype=np.float32), min_face_size=size)
    # Lights: non-finite or absurd values are refused, never turned into NaN lights.
    for bad in (float("nan"), float("inf"), 1e308):
        with pytest.raises(facetool.Error, match="DPR light"):
            facetool.light_from_dpr([bad] + [0.0] * 8)
        with pytest.raises(facetool.Error, match="SfSNet light"):
            facetool.light_from_sfsnet([bad] + [0.0] * 26)
    with pytest.raises(ValueError, match="within"):
        facetool.light_to_dpr(np.full((3, 9), 1e38))
    # Paths: a NUL byte would cut the path short; an empty weights path is not the shipped model.
    with pytest.raises(ValueError, match="NUL"):
        model.decompose_file(PHOTO + "\x00junk")
    with pytest.raises(ValueError, match="empty path"):
        facetool.load_model("")
    # A binary file read as a light: the message names it, printable (not an empty message).
    with tempfile.TemporaryDirectory() as folder:
        junk = os.path.join(folder, "junk.txt")
        with open(junk, "wb") as f:
            f.write(bytes(range(256)) * 2)
        with pytest.raises(facetool.Error, match="junk.txt") as caught:
            facetool.read_light(junk)
        assert "\\x" in str(caught.value)


@needs_photo_model
def test_no_face_and_bad_relight_inputs(model, photo):
    with pytest.raises(facetool.Error, match="no face found"):
        model.decompose(np.full((200, 300, 3), 0.5, dtype=np.float32))
    # The photo's 8-bit values given as floats: the message says how floats are read.
    with pytest.raises(facetool.Error, match="linear RGB in 0..1"):
        model.decompose(np.clip(facetool.read_image(PHOTO), 0, 1) ** (1 / 2.2) * 255)
    with pytest.raises(facetool.Error, match="does-not-exist.png"):
        model.decompose_file("does-not-exist.png")
    with pytest.raises(ValueError, match="mode"):
        model.relight(photo, photo.faces[0].light_photo, mode="bogus")
    with pytest.raises(ValueError, match=r"\(3, 9\)"):
        model.relight(photo, np.zeros(10))
    with pytest.raises(TypeError):
        model.relight("not a photo", photo.faces[0].light_photo)


LAYERS = {"albedo": 3, "normal": 3, "visibility": 9, "shading": 3, "reconstruction": 3}


@needs_photo_model
@pytest.mark.parametrize("asked", [["normal"], ["albedo", "shading"], "visibility", ["reconstruction"]])
def test_layers_gives_the_full_decompositions_arrays_for_those_asked_and_an_error_for_the_others(photo, model, asked):
    # The reference: the `photo` fixture, a decompose of the same file with every layer.
    part = model.decompose_file(PHOTO, layers=asked)
    names = [asked] if isinstance(asked, str) else asked
    np.testing.assert_array_equal(part.alpha, photo.alpha)
    for name, channels in LAYERS.items():
        if name in names:
            got = getattr(part, name)
            assert got.shape == photo.image.shape[:2] + (channels,)
            np.testing.assert_array_equal(got, getattr(photo, name))  # the same computation: equal exactly
        else:
            with pytest.raises(facetool.Error, match=r"layers=") as raised:
                getattr(part, name)
            assert f"the photo's {name} layer was not computed" in str(raised.value)
    # The faces (crop-level results, lights, coverage) are computed whatever the list.
    for mine, full in zip(part.faces, photo.faces):
        np.testing.assert_array_equal(mine.normal, full.normal)
        np.testing.assert_array_equal(mine.albedo, full.albedo)
        np.testing.assert_array_equal(mine.light_photo, full.light_photo)
        np.testing.assert_array_equal(mine.coverage, full.coverage)


@needs_photo_model
def test_layers_from_an_array_and_bad_layer_names(model):
    image = facetool.read_image(PHOTO)
    full = model.decompose(image)
    normal_only = facetool.decompose(image, model=model, layers=["normal"])
    np.testing.assert_array_equal(normal_only.normal, full.normal)
    with pytest.raises(facetool.Error, match="layers="):
        normal_only.albedo
    # Ratio relighting reads the shading layer: a photo without it says so.
    with pytest.raises(facetool.Error, match="shading"):
        model.relight(normal_only, full.faces[0].light_photo)
    with pytest.raises(ValueError, match="unknown layer 'normals'.*albedo, normal, visibility, shading, reconstruction"):
        model.decompose(image, layers=["normals"])
    with pytest.raises(ValueError, match="empty list"):
        model.decompose(image, layers=[])
    with pytest.raises(ValueError, match="named twice"):
        model.decompose(image, layers=["normal", "normal"])
    with pytest.raises(TypeError, match="layers"):
        model.decompose(image, layers=3)


@needs_photo_model
def test_gil_is_released_during_compute(model):
    image = facetool.read_image(PHOTO)
    done = threading.Event()
    ticks = 0

    def work():
        model.decompose(image)
        done.set()

    worker = threading.Thread(target=work)
    worker.start()
    while not done.is_set():  # runs only while the worker's call does not hold the GIL
        ticks += 1
    worker.join()
    assert ticks > 1000


def _run_under_memory_limit(setup, code, headroom_mb):
    """Runs `setup`, then `code` under an address-space limit of what the interpreter uses after
    the setup plus `headroom_mb`, in a fresh interpreter; returns its (returncode, stdout, stderr)."""
    script = ("import resource, sys, numpy, facetool\n" + setup +
              "used = int(open('/proc/self/statm').read().split()[0]) * resource.getpagesize()\n"
              f"limit = used + {headroom_mb} * 2**20\n"
              "resource.setrlimit(resource.RLIMIT_AS, (limit, limit))\n" + code)
    done = subprocess.run([os.sys.executable, "-c", script], capture_output=True, text=True, timeout=120,
                          env=dict(os.environ))
    return done.returncode, done.stdout, done.stderr


def test_out_of_memory_is_a_memory_error_naming_the_task():
    # Under a limit that leaves 20 MB, loading the model raises MemoryError naming the task and
    # about how much it needs (issue 55: a bare "std::bad_alloc", or the interpreter aborted).
    code = ("try:\n    facetool.load_model()\n    print('loaded')\n"
            "except MemoryError as e:\n    print('MemoryError:', e)\n")
    rc, out, err = _run_under_memory_limit("", code, 20)
    assert rc == 0, err
    if out.startswith("loaded"):
        pytest.skip("the model loaded within 20 MB more (nothing to check)")
    assert out.startswith("MemoryError: out of memory while"), out + err
    assert "needs ~" in out and "bad_alloc" not in out


@needs_photo_model
def test_detection_under_a_memory_limit_ends_with_a_memory_error():
    # Detection calls into OpenBLAS, which retries a failed allocation forever: with the model
    # loaded and 100 MB left, decompose must end (the subprocess's timeout) with a MemoryError.
    code = (f"try:\n    m.decompose_file({PHOTO!r})\n    print('decomposed')\n"
            "except MemoryError as e:\n    print('MemoryError:', e)\n")
    rc, out, err = _run_under_memory_limit("m = facetool.load_model()\n", code, 100)
    assert rc == 0, err
    assert out.startswith("MemoryError: out of memory while"), out + err


@needs_photo_model
@pytest.mark.skipif("opencl" not in facetool.backends(), reason="no OpenCL device")
def test_opencl_model_in_a_forked_child_says_so_instead_of_hanging():
    # OpenCL's driver threads are not copied by fork: a child's decompose never ended (issue 55).
    # It must raise facetool.Error naming the fork; the cpu backend works in a child.
    code = (f"import os, signal\n"
            f"for backend in ('opencl', 'cpu'):\n"
            f"    m = facetool.load_model(backend=backend)\n"
            f"    m.decompose_file({PHOTO!r})\n"
            f"    pid = os.fork()\n"
            f"    if pid == 0:\n"
            f"        signal.alarm(60)\n"
            f"        try:\n"
            f"            m.decompose_file({PHOTO!r})\n"
            f"            print(backend, 'decomposed', flush=True)\n"
            f"        except facetool.Error as e:\n"
            f"            print(backend, 'Error:', e, flush=True)\n"
            f"        os._exit(0)\n"
            f"    os.waitpid(pid, 0)\n")
    done = subprocess.run([os.sys.executable, "-c", "import facetool\n" + code], capture_output=True, text=True,
                          timeout=180, env=dict(os.environ))
    lines = done.stdout.splitlines()
    assert any(l.startswith("opencl Error:") and "fork" in l for l in lines), done.stdout + done.stderr
    assert "cpu decomposed" in lines, done.stdout + done.stderr


def _page_data(html):
    """The data block of a view page (libs/view/page/view.html's facetool-data script)."""
    start = html.index('id="facetool-data">') + len('id="facetool-data">')
    return json.loads(html[start:html.index("</script>", start)])


def _planes(face):
    """A page face's packed crop layers decoded as the page decodes them: [18, S*S]."""
    import base64
    s = face["crop_size"]
    q = np.frombuffer(base64.b64decode(face["planes"]), "<u2").reshape(18, s * s).astype(np.float64)
    lo, hi = np.array(face["ranges"][0::2])[:, None], np.array(face["ranges"][1::2])[:, None]
    return lo + q * (hi - lo) / 65535


@needs_photo_model
def test_view_page_equals_the_programs(photo):
    """facetool.view(photo, path) writes the page `facetool view` writes for infer's folder of the same
    photo: the same layers (PNG bytes), faces, masks, lights and presets; faces.json's landmarks and
    transforms are printed to 9 digits, hence the tolerances on what is derived from them."""
    exe = os.environ.get("FACETOOL_EXE")
    if not exe:
        pytest.skip("FACETOOL_EXE not set (run through ctest)")
    with tempfile.TemporaryDirectory() as out:
        subprocess.run([exe, "infer", PHOTO, "-o", out, "--no-contact-sheet", "--view"], check=True, capture_output=True)
        program = _page_data(open(os.path.join(out, "astronaut", "view.html"), encoding="utf-8").read())
        path = os.path.join(out, "from_python.html")
        facetool.view(photo, path)
        html = open(path, encoding="utf-8").read()
    ours = _page_data(html)
    assert html.startswith("<!DOCTYPE html>") and "facetoolView" in html
    for key in ["name", "source", "width", "height", "feather", "mask_shape", "photo", "mask", "layers", "triple"]:
        assert ours[key] == program[key], key
    assert [p["name"] for p in ours["presets"]] == [p["name"] for p in program["presets"]]
    for a, b in zip(ours["presets"], program["presets"]):
        np.testing.assert_allclose(a["light"], b["light"], rtol=1e-6, atol=1e-7)
    assert len(ours["faces"]) == len(program["faces"]) == len(photo.faces)
    for a, b in zip(ours["faces"], program["faces"]):
        for key in ["folder", "crop_size", "region"]:
            assert a[key] == b[key], key
        for key in ["photo_to_crop", "landmarks", "box", "mask_lines", "light", "to_crop"]:
            np.testing.assert_allclose(np.array(a[key], float), np.array(b[key], float), rtol=1e-6, atol=1e-6, err_msg=key)
        np.testing.assert_allclose(_planes(a), _planes(b), atol=1e-6)


@needs_photo_model
def test_photo_shows_its_view_page_in_a_notebook(photo):
    """A Photo's _repr_html_ (Jupyter) is an iframe whose srcdoc holds its whole view page."""
    import html as html_module
    shown = photo._repr_html_()
    assert shown.startswith("<iframe") and 'srcdoc="' in shown
    srcdoc = html_module.unescape(shown[shown.index('srcdoc="') + 8:shown.rindex('"')])
    assert srcdoc == photo.view_html().decode("utf-8")
    assert _page_data(srcdoc)["width"] == photo.image.shape[1]
    with pytest.raises(TypeError, match="facetool.Photo"):
        facetool.view("not a photo", "x.html")
