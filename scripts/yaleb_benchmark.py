#!/usr/bin/env python3
"""Real-photo normal benchmark on Extended Yale B: photometric-stereo reference normals, baselines, scoring.

    /usr/bin/python3 scripts/yaleb_benchmark.py [--data DIR] [--cache DIR] COMMAND ...
      ps                                   reference normals, albedo, reliability masks
      ps-halves                            how far apart PS from alternate halves of the strobes is
      infer  [--facetool BIN] [--model W --name NAME]   a model (as given, padded, --aligned --stretch)
      fit    --fit-bin BIN                 `BIN fit` on the evaluation photos (each alone, padded,
                                           and each subject's as one still head)
      relight [--model W --name NAME]      frontal photos relit to the +-25 degree lights: PSNR
      score  [--pred NAME=DIR ...] [--markdown FILE]
      light  [--facetool BIN] [--name NAME] [--infer-args '...'] [--relight-args '...'] [--reuse]
             [--markdown FILE]             the light infer estimates (below)
      run    [--facetool BIN] [--fit-bin BIN] [--fit-dir DIR] [--markdown FILE]   all of it
             (ps, infer, fit with --fit-bin, score, light)

`ps` solves Lambertian photometric stereo per subject from its single-strobe photos (ambient
subtracted; strobes within 80 degrees of the camera axis; saturated and shadowed samples never
used; least squares with attached shadows and outliers rejected and solved again; one intensity
gain per strobe calibrated over all subjects) and writes `CACHE/ps/<subject>/normal.exr`
(camera frame: +X the viewer's right, +Y up, +Z towards the camera; (0,0,0) where unreliable),
`albedo.exr`, `reliable.exr` (the reliability mask), `diagnostics.exr` and `stats.json`.
`infer` runs `facetool infer` on the evaluation photos (the frontal, +-25 and +-50 degree
azimuth strobes at elevation 0): as given, padded (cut back to the photo), and `--aligned --stretch`;
it also gathers each subject's landmarks for the template. `score` scores every prediction
folder (`DIR/<photo stem>/normal.exr`, or infer's `photo.exr`) against the PS normals inside the
reliability mask (where the template is defined), with the constant normal and a leave-one-out
mean-face template on the same pixels (for the fit also the template placed by each photo's own
landmarks), and prints the tables (the paper's Table 1 form, plus coverage).
`light` runs `facetool infer --no-contact-sheet` once on every strobe photo within 90 degrees of
the camera axis (padded, and sRGB-encoded as a camera writes photos: Yale B's values are linear)
and scores the light of each photo's largest face: the direction of its
first SH band against the strobe's and |L1|/L0, by the strobe's angle from the axis (and checks
the sign convention); each strobe photo's albedo against the frontal photo's and the PS albedo
(the raw photos as the baseline); and the frontal photo relit to seven strobes by `facetool
relight --light-from` against ratio relights with the true direction (facetool's normals, the PS
normals) and the unchanged photo (PSNR); its results go to CACHE/light/NAME.
docs/benchmarks.md has the method and the figures. The data stays where it is; all
output goes to the cache (default build/yaleb).
"""
import argparse
import json
import math
import os
import re
import shlex
import shutil
import struct
import subprocess
import sys
import time
import warnings

try:
    import numpy as np
except ImportError:
    sys.exit("yaleb_benchmark: needs numpy (Debian: python3-numpy; run it with /usr/bin/python3)")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_DATA = os.path.join(ROOT, "..", "shared", "assets", "faces", "yaleb-dev")
DEFAULT_CACHE = os.path.join(ROOT, "build", "yaleb")
DEFAULT_FACE_MODEL = os.path.join(ROOT, "..", "shared", "assets", "ict-facekit", "FaceXModel")
NAME_RE = re.compile(r"^(yaleB\d+)_P00A([+-]\d{3})E([+-]\d{2})\.pgm$")
EVAL_LIGHTS = [(0, 0), (25, 0), (-25, 0), (50, 0), (-50, 0)]   # (azimuth, elevation), degrees

# Yale B's azimuth sign in the camera frame (x = AZIMUTH_SIGN sin(a) cos(e)): a positive azimuth
# lights the viewer's left (the subject's right) side of the image. `ps` re-checks it on the
# images (which half of the face is brighter) and stops if the photos say otherwise.
AZIMUTH_SIGN = -1.0

# Photometric-stereo thresholds, in 8-bit camera units (DN) unless said otherwise.
SATURATED_DN = 250          # a sample at or above this raw value is rejected (clipped)
SHADOW_DN = 4.0             # below this (after ambient subtraction) a sample is a shadow
SHADOW_RELATIVE = 0.06      # ... or below this fraction of the pixel's 90th-percentile value
NOISE_DN = 1.5              # floor of the residual scale used to reject outliers
OUTLIER_SIGMAS = 3.0        # |residual| above this many robust sigmas: cast shadow/specularity
ITERATIONS = 6
MAX_LIGHT_ANGLE = 80.0      # strobes further than this from the camera axis (degrees) are not used
GAIN_ROUNDS = 3             # rounds of the per-strobe intensity calibration (0: all gains 1)
GAIN_STRIDE = 3             # the calibration uses every GAIN_STRIDE-th pixel in each direction
# The reliability mask: a pixel's PS normal is trusted when all of these hold.
MIN_LIGHTS = 12             # inlier lights
MAX_CONDITION = 6.0         # sqrt(largest / smallest eigenvalue) of the inlier directions' Gram
MAX_RELATIVE_RESIDUAL = 0.15  # RMS residual / mean intensity over the inliers
MIN_ALBEDO_FRACTION = 0.15  # albedo / the subject's median albedo


def fail(message):
    sys.exit(f"yaleb_benchmark: {message}")


# ----------------------------------------------------------------------------------------- I/O

def read_pgm(path):
    """An 8- or 16-bit binary PGM (P5) as a float32 array (rows top to bottom)."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        fail(f"cannot read {path}: {e.strerror}")
    fields, pos = [], 0
    while len(fields) < 4:
        while pos < len(data) and data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            while pos < len(data) and data[pos:pos + 1] not in (b"\n", b"\r"):
                pos += 1
            continue
        start = pos
        while pos < len(data) and not data[pos:pos + 1].isspace():
            pos += 1
        if start == pos:
            fail(f"{path}: truncated PGM header")
        fields.append(data[start:pos])
    if fields[0] != b"P5":
        fail(f"{path}: not a binary PGM (P5)")
    try:
        width, height, maxval = (int(v) for v in fields[1:])
    except ValueError:
        width = height = maxval = 0
    if not (0 < width <= 32768 and 0 < height <= 32768 and 0 < maxval < 65536):
        fail(f"{path}: a damaged PGM header (size or maximum value)")
    dtype = np.dtype(">u2") if maxval > 255 else np.dtype("u1")
    pixels = data[pos + 1:pos + 1 + width * height * dtype.itemsize]
    if len(pixels) != width * height * dtype.itemsize:
        fail(f"{path}: truncated PGM pixels")
    return np.frombuffer(pixels, dtype).reshape(height, width).astype(np.float32) * (255.0 / maxval)


def oiio():
    try:
        import OpenImageIO
    except ImportError:
        fail("needs OpenImageIO's Python module (Debian: python3-openimageio; "
             "scripts/install-dependencies.sh installs it)")
    return OpenImageIO


def write_exr(path, image, channels):
    """Writes an H x W x C float32 image to an EXR (to a temporary name, then renamed)."""
    OpenImageIO = oiio()
    image = np.ascontiguousarray(image, dtype=np.float32)
    if image.ndim == 2:
        image = image[:, :, None]
    spec = OpenImageIO.ImageSpec(image.shape[1], image.shape[0], image.shape[2], "float")
    spec.channelnames = tuple(channels)
    spec.attribute("compression", "zip")
    tmp = f"{path}.tmp-{os.getpid()}.exr"
    out = OpenImageIO.ImageOutput.create(tmp)
    if out is None or not out.open(tmp, spec) or not out.write_image(image) or not out.close():
        fail(f"cannot write {path}: {OpenImageIO.geterror()}")
    os.replace(tmp, path)


def write_png8(path, grey):
    """Writes an H x W array of 0..255 values as an 8-bit grey PNG."""
    OpenImageIO = oiio()
    spec = OpenImageIO.ImageSpec(grey.shape[1], grey.shape[0], 1, "uint8")
    out = OpenImageIO.ImageOutput.create(path)
    data = np.ascontiguousarray(np.clip(np.rint(grey), 0, 255).astype(np.uint8)[:, :, None])
    if out is None or not out.open(path, spec) or not out.write_image(data) or not out.close():
        fail(f"cannot write {path}: {OpenImageIO.geterror()}")


def read_exr_channels(path):
    """An image file as (H x W x C float32, channel names)."""
    OpenImageIO = oiio()
    inp = OpenImageIO.ImageInput.open(path)
    if inp is None:
        fail(f"cannot read {path}: {OpenImageIO.geterror()}")
    spec = inp.spec()
    pixels = inp.read_image("float")
    inp.close()
    if pixels is None:
        fail(f"cannot read the pixels of {path}")
    pixels = np.asarray(pixels, np.float32).reshape(spec.height, spec.width, spec.nchannels)
    return pixels, list(spec.channelnames)


def read_normal_prediction(path):
    """A predicted normal map: (H x W x 3 unit normals, H x W valid mask) from `normal.exr`
    (3 channels, (0,0,0) where not covered) or infer's `photo.exr` (normal.X/Y/Z premultiplied
    by A)."""
    pixels, names = read_exr_channels(path)
    if all(c in names for c in ("normal.X", "normal.Y", "normal.Z")):
        n = np.stack([pixels[:, :, names.index(c)] for c in ("normal.X", "normal.Y", "normal.Z")], -1)
        alpha = pixels[:, :, names.index("A")] if "A" in names else np.ones(n.shape[:2], np.float32)
        valid = alpha >= 0.5
        n = n / np.maximum(alpha, 1e-6)[:, :, None]
    elif pixels.shape[2] >= 3:
        n = pixels[:, :, :3]
        valid = np.ones(n.shape[:2], bool)
    else:
        fail(f"{path}: expected 3 normal channels or normal.X/Y/Z, found {names}")
    length = np.linalg.norm(n, axis=-1)
    valid &= np.isfinite(length) & (length > 0.5)
    n = np.where(valid[:, :, None], n / np.maximum(length, 1e-12)[:, :, None], 0.0)
    return n.astype(np.float32), valid


# ----------------------------------------------------------------------- photometric stereo

def light_direction(azimuth_deg, elevation_deg, azimuth_sign=AZIMUTH_SIGN):
    """Unit direction towards a strobe in the camera frame (+X right, +Y up, +Z to the viewer)."""
    a, e = math.radians(azimuth_deg), math.radians(elevation_deg)
    return np.array([azimuth_sign * math.sin(a) * math.cos(e), math.sin(e),
                     math.cos(a) * math.cos(e)])


def solve_photometric_stereo(intensity, raw, lights, saturated=SATURATED_DN,
                             iterations=ITERATIONS):
    """Robust Lambertian photometric stereo.

    intensity: K x H x W (ambient subtracted), raw: K x H x W (the recorded values, for the
    saturation test), lights: K x 3 unit directions. Returns a dict of H x W (x 3) arrays:
    normal, albedo, lights (inlier count), condition, residual (relative RMS), reliable.
    Per pixel: samples that are saturated or below the shadow threshold are never used; the
    scaled normal b = albedo * n solves the inlier least squares sum_k (I_k - l_k . b)^2, then
    samples the model predicts in attached shadow (l_k . b <= 0) or whose residual exceeds
    OUTLIER_SIGMAS robust sigmas (1.4826 x median |residual|, floored) are dropped and it is
    solved again, ITERATIONS times.
    """
    k, h, w = intensity.shape
    i_flat = intensity.reshape(k, -1).astype(np.float64)
    raw_flat = raw.reshape(k, -1)
    lights = np.asarray(lights, np.float64)
    usable = raw_flat < saturated
    q90 = np.nanpercentile(np.where(usable, i_flat, np.nan), 90, axis=0)
    q90 = np.nan_to_num(q90, nan=0.0)
    base = usable & (i_flat > np.maximum(SHADOW_DN, SHADOW_RELATIVE * q90)[None, :])
    inlier = base.copy()
    outer = np.einsum("ki,kj->kij", lights, lights)          # K x 3 x 3
    b = np.zeros((i_flat.shape[1], 3))
    for _ in range(iterations + 1):
        weights = inlier.astype(np.float64)
        gram = np.einsum("kp,kij->pij", weights, outer)
        rhs = np.einsum("kp,kp,ki->pi", weights, i_flat, lights)
        solvable = inlier.sum(0) >= 3
        gram[~solvable] = np.eye(3)
        rhs[~solvable] = 0.0
        b = np.linalg.solve(gram + 1e-9 * np.eye(3), rhs[:, :, None])[:, :, 0]
        prediction = lights @ b.T                              # K x P
        residual = i_flat - prediction
        abs_res = np.where(inlier, np.abs(residual), np.nan)
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)   # pixels without any inlier
            sigma = 1.4826 * np.nanmedian(abs_res, axis=0)
        sigma = np.maximum(np.nan_to_num(sigma, nan=NOISE_DN), np.maximum(NOISE_DN, 0.02 * q90))
        new = base & (prediction > 0) & (np.abs(residual) <= OUTLIER_SIGMAS * sigma[None, :])
        if np.array_equal(new, inlier):
            break
        inlier = new
    count = inlier.sum(0)
    gram = np.einsum("kp,kij->pij", inlier.astype(np.float64), outer)
    eig = np.linalg.eigvalsh(gram)                              # ascending
    condition = np.sqrt(np.maximum(eig[:, 2], 1e-12) / np.maximum(eig[:, 0], 1e-12))
    residual = i_flat - lights @ b.T
    with np.errstate(all="ignore"):
        rms = np.sqrt((np.where(inlier, residual, 0.0) ** 2).sum(0) / np.maximum(count, 1))
        mean_i = np.where(inlier, i_flat, 0.0).sum(0) / np.maximum(count, 1)
        relative = rms / np.maximum(mean_i, 1e-6)
    albedo = np.linalg.norm(b, axis=1)
    normal = b / np.maximum(albedo, 1e-12)[:, None]
    good_albedo = albedo[(count >= MIN_LIGHTS) & (albedo > 0)]
    median_albedo = float(np.median(good_albedo)) if good_albedo.size else 0.0
    reliable = ((count >= MIN_LIGHTS) & (condition <= MAX_CONDITION)
                & (relative <= MAX_RELATIVE_RESIDUAL) & (normal[:, 2] > 0)
                & (albedo >= MIN_ALBEDO_FRACTION * median_albedo))
    return {
        "normal": normal.reshape(h, w, 3).astype(np.float32),
        "albedo": albedo.reshape(h, w).astype(np.float32),
        "lights": count.reshape(h, w),
        "condition": condition.reshape(h, w).astype(np.float32),
        "residual": relative.reshape(h, w).astype(np.float32),
        "reliable": reliable.reshape(h, w),
    }


def list_subject(folder):
    """The strobe photos of one subject folder: [(azimuth, elevation, path)], and the ambient."""
    photos, ambient = [], None
    for name in sorted(os.listdir(folder)):
        m = NAME_RE.match(name)
        if m:
            photos.append((int(m.group(2)), int(m.group(3)), os.path.join(folder, name)))
        elif name.endswith("_Ambient.pgm"):
            ambient = os.path.join(folder, name)
    return photos, ambient


def subjects(data):
    if not os.path.isdir(data):
        fail(f"no Yale B folder at {data} (pass --data: the yaleb-dev folder of ../shared)")
    found = sorted(d for d in os.listdir(data) if re.fullmatch(r"yaleB\d+", d)
                   and os.path.isdir(os.path.join(data, d)))
    if not found:
        fail(f"{data} holds no yaleBNN subject folder")
    return found


def load_subject(data, subject):
    photos, ambient = list_subject(os.path.join(data, subject))
    if len(photos) < 16:
        fail(f"{subject}: only {len(photos)} strobe photos found (expected 64)")
    raw = np.stack([read_pgm(p) for _, _, p in photos])
    amb = read_pgm(ambient) if ambient else np.zeros_like(raw[0])
    intensity = np.maximum(raw - amb[None], 0.0)
    return photos, raw, intensity


def half_contrast(data, names, bright, dark, axis):
    """Per subject, (first half - second half) brightness of photo `bright` minus photo `dark`
    (name suffixes like A+050E+00), over the mean of both; halves along `axis` (1: left/right
    of the image, 0: top/bottom)."""
    votes = []
    for s in names:
        folder = os.path.join(data, s)
        paths = [os.path.join(folder, f"{s}_P00{x}.pgm") for x in (bright, dark)]
        if not all(os.path.exists(p) for p in paths):
            continue
        p, m = (read_pgm(x) for x in paths)
        half = p.shape[axis] // 2
        first = np.take(p, range(half), axis).mean() - np.take(m, range(half), axis).mean()
        second = (np.take(p, range(half, p.shape[axis]), axis).mean()
                  - np.take(m, range(half, p.shape[axis]), axis).mean())
        votes.append(float((first - second) / max(1e-6, 0.5 * (p.mean() + m.mean()))))
    return votes


def check_signs(data, names):
    """Checks the light-direction convention on the photos: a positive azimuth must light the
    image's left half (the subject's right), a positive elevation the upper half. A global
    mirror of all lights is invisible to the least-squares residual (it mirrors the normals
    instead), so the photos themselves are the only check."""
    checks = [("azimuth", "A+050E+00", "A-050E+00", 1, AZIMUTH_SIGN < 0,
               "A+050 vs A-050: left half brighter"),
              ("elevation", "A+000E+45", "A+000E-35", 0, True,
               "A+000E+45 vs A+000E-35: upper half brighter")]
    evidence = {}
    for what, bright, dark, axis, expect_first, text in checks:
        votes = half_contrast(data, names, bright, dark, axis)
        if not votes:
            fail(f"no {bright} / {dark} pair to check the {what} sign against")
        yes = sum(1 for v in votes if v > 0)
        print(f"{what} sign: {text} in {yes} of {len(votes)} subjects (mean relative contrast "
              f"{np.mean(votes):+.2f})")
        if (yes == len(votes)) != expect_first or (0 < yes < len(votes)):
            fail(f"the photos contradict the {what} sign convention: check the data")
        evidence[what] = votes
    return evidence


def used_lights(photos):
    """Indices and camera-frame directions of the strobes within MAX_LIGHT_ANGLE of the axis."""
    keep = [i for i, (a, e, _) in enumerate(photos)
            if math.degrees(math.acos(light_direction(a, e)[2])) <= MAX_LIGHT_ANGLE + 1e-9]
    return keep, np.stack([light_direction(photos[i][0], photos[i][1]) for i in keep])


def calibrate_gains(stack, lights, rounds=GAIN_ROUNDS, stride=GAIN_STRIDE):
    """Relative strobe intensities shared by all subjects (one rig): alternately solve the PS
    on a pixel subsample of every subject and set each strobe's gain to the median ratio of
    recorded to predicted intensity over well-fitted pixels; median gain 1. stack: list of
    (raw, intensity) K x H x W pairs. Returns K gains and the median relative residual per
    round (before each update)."""
    gains = np.ones(len(lights))
    history = []
    for _ in range(rounds):
        ratios, residuals = [], []
        for raw, intensity in stack:
            sub_i = intensity[:, ::stride, ::stride] / gains[:, None, None]
            sub_r = raw[:, ::stride, ::stride]
            r = solve_photometric_stereo(sub_i, sub_r, lights)
            b = (r["normal"] * r["albedo"][..., None]).reshape(-1, 3)
            pred = lights @ b.T
            good = (r["lights"].reshape(-1) >= MIN_LIGHTS) & (r["residual"].reshape(-1) < 0.25)
            i_flat = sub_i.reshape(len(lights), -1)
            ok = (pred > 20) & (sub_r.reshape(len(lights), -1) < SATURATED_DN) & good[None]
            ratios.append(np.where(ok, i_flat / np.maximum(pred, 1e-6), np.nan))
            residuals.append(r["residual"][r["lights"] >= MIN_LIGHTS])
        history.append(float(np.median(np.concatenate(residuals))))
        update = np.nan_to_num(np.nanmedian(np.concatenate(ratios, 1), axis=1), nan=1.0)
        gains *= update
        gains /= np.median(gains)
    return gains, history


def command_ps(args):
    names = subjects(args.data)
    evidence = check_signs(args.data, names)
    loaded = {}
    for s in names:
        photos, raw, intensity = load_subject(args.data, s)
        keep, lights = used_lights(photos)
        loaded[s] = (photos, raw[keep], intensity[keep], lights, [photos[i][:2] for i in keep])
    light_sets = {tuple(map(tuple, v[4])) for v in loaded.values()}
    if len(light_sets) != 1:
        fail("the subjects do not share one set of strobes; cannot calibrate gains jointly")
    lights, light_names = next(iter(loaded.values()))[3], next(iter(loaded.values()))[4]
    print(f"using {len(lights)} of {len(next(iter(loaded.values()))[0])} strobes (within "
          f"{MAX_LIGHT_ANGLE:.0f} degrees of the camera axis); calibrating their gains", flush=True)
    gains, history = calibrate_gains([(v[1], v[2]) for v in loaded.values()], lights)
    print("median relative residual by calibration round: "
          + ", ".join(f"{h:.3f}" for h in history)
          + f"; gains {gains.min():.2f}..{gains.max():.2f}", flush=True)
    summary = {}
    for idx, s in enumerate(names):
        photos, raw, intensity, _, _ = loaded[s]
        out_dir = os.path.join(args.cache, "ps", s)
        os.makedirs(out_dir, exist_ok=True)
        result = solve_photometric_stereo(intensity / gains[:, None, None], raw, lights)
        rel = result["reliable"]
        w = rel.shape[1]
        h = rel.shape[0]
        stats = {
            "lights_used": len(lights),
            "reliable_pixels": int(rel.sum()),
            "reliable_fraction": float(rel.mean()),
            "median_inlier_lights": float(np.median(result["lights"][rel])) if rel.any() else 0,
            "median_relative_residual": float(np.median(result["residual"][rel])) if rel.any() else 0,
            "mean_nx_left_third": float(result["normal"][:, : w // 3, 0][rel[:, : w // 3]].mean()),
            "mean_nx_right_third": float(result["normal"][:, 2 * w // 3:, 0][rel[:, 2 * w // 3:]].mean()),
            "mean_ny_top_fifth": float(result["normal"][: h // 5, :, 1][rel[: h // 5]].mean()),
        }
        normal = np.where(rel[:, :, None], result["normal"], 0.0)
        write_exr(os.path.join(out_dir, "normal.exr"), normal, ("R", "G", "B"))
        write_exr(os.path.join(out_dir, "albedo.exr"), result["albedo"] / 255.0, ("Y",))
        write_exr(os.path.join(out_dir, "reliable.exr"), rel.astype(np.float32), ("Y",))
        write_exr(os.path.join(out_dir, "diagnostics.exr"),
                  np.stack([result["lights"], result["condition"], result["residual"]], -1),
                  ("lights", "condition", "residual"))
        with open(os.path.join(out_dir, "stats.json"), "w") as f:
            json.dump(stats, f, indent=1)
        summary[s] = stats
        print(f"[{idx + 1}/{len(names)}] {s}: reliable {100 * stats['reliable_fraction']:.1f} % of "
              f"the photo, median inlier lights {stats['median_inlier_lights']:.0f}, median "
              f"relative residual {stats['median_relative_residual']:.3f}, mean n_x left third "
              f"{stats['mean_nx_left_third']:+.2f} right third {stats['mean_nx_right_third']:+.2f}, "
              f"mean n_y top fifth {stats['mean_ny_top_fifth']:+.2f}", flush=True)
    with open(os.path.join(args.cache, "ps", "summary.json"), "w") as f:
        json.dump({"sign_evidence": evidence, "lights": light_names,
                   "gains": [float(g) for g in gains], "calibration_residuals": history,
                   "subjects": summary}, f, indent=1)


def strobe_halves(lights):
    """Two halves of the strobes (index arrays) that both span all directions: the strobes
    sorted by their direction's angle about the camera axis, taken alternately."""
    order = np.argsort(np.arctan2(lights[:, 1], lights[:, 0]), kind="stable")
    return np.sort(order[0::2]), np.sort(order[1::2])


def halves_disagreement(intensity, raw, lights):
    """PS solved from each half of the strobes (`strobe_halves`): the angles (degrees) between
    the two solutions where both and the full solution are reliable, and that mask."""
    full = solve_photometric_stereo(intensity, raw, lights)
    a, b = (solve_photometric_stereo(intensity[h], raw[h], lights[h]) for h in strobe_halves(lights))
    mask = full["reliable"] & a["reliable"] & b["reliable"]
    return angular_error_deg(a["normal"][mask], b["normal"][mask]), mask, full["reliable"]


def command_ps_halves(args):
    """The reference's random error: per subject, how far apart the PS solutions from the two
    halves of the strobes are, with the gains of `ps`. The full set's random error is about half
    of that (each half has half the strobes, and the difference of two independent errors is
    sqrt(2) times either). Systematic errors (subsurface scattering, interreflections) are
    common to both halves and not measured."""
    summary_path = os.path.join(args.cache, "ps", "summary.json")
    if not os.path.exists(summary_path):
        fail(f"no {summary_path}: run `ps` first")
    with open(summary_path) as f:
        gains = np.array(json.load(f)["gains"])
    means = []
    for s in subjects(args.data):
        photos, raw, intensity = load_subject(args.data, s)
        keep, lights = used_lights(photos)
        angle, mask, reliable = halves_disagreement(intensity[keep] / gains[:, None, None], raw[keep], lights)
        means.append(float(angle.mean()))
        print(f"{s}: the halves' normals {angle.mean():.2f} degrees apart (median {np.median(angle):.2f}) on "
              f"{100 * mask.sum() / max(1, reliable.sum()):.1f} % of the reliability mask", flush=True)
    print(f"mean over {len(means)} subjects: {np.mean(means):.2f} degrees apart; the full set's random error "
          f"about {np.mean(means) / 2:.1f} degrees")


# ------------------------------------------------------------------------ evaluation photos

def eval_stem(subject, azimuth, elevation):
    return f"{subject}_P00A{azimuth:+04d}E{elevation:+03d}"


def eval_photos(data):
    """[(subject, stem, path)] of the evaluation photos that exist (frontal, +-25, +-50 at E 0)."""
    out = []
    for s in subjects(data):
        for a, e in EVAL_LIGHTS:
            stem = eval_stem(s, a, e)
            path = os.path.join(data, s, stem + ".pgm")
            if os.path.exists(path):
                out.append((s, stem, path))
    return out


def landmark_photos(data, s):
    """Photos of subject s lit near the camera axis (within 25 degrees), for its landmarks: the
    pose is the same under every strobe, so any well-lit photo gives the subject's landmarks."""
    photos, _ = list_subject(os.path.join(data, s))
    near = [(abs(a) + abs(e), p) for a, e, p in photos if abs(a) <= 25 and abs(e) <= 25]
    return [p for _, p in sorted(near)]


def run_facetool(cmd, log_path):
    """Runs a facetool command, its output to a log; returns the exit status (1 = some photo
    failed, which is expected here: the detector misses faces)."""
    with open(log_path, "w") as log:
        status = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT)
    if status not in (0, 1):
        fail(f"{' '.join(cmd)} exited with {status}; see {log_path}")
    return status


def find_facetool(path):
    candidates = [path] if path else [os.path.join(ROOT, "build", "bin", "facetool"),
                                      shutil.which("facetool")]
    for c in candidates:
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    fail("no facetool program: build it (scripts/build.sh) or pass --facetool BIN")


def takes_fit_prior(weights):
    """Whether a weights file's network takes the fit's normals as input (its safetensors header's
    metadata 'input' is linear_rgb+fit_normal, docs/model-format.md)."""
    if not weights:
        return False
    with open(weights, "rb") as f:
        size = struct.unpack("<Q", f.read(8))[0]
        header = json.loads(f.read(size))
    return header.get("__metadata__", {}).get("input", "linear_rgb") != "linear_rgb"


def model_options(args):
    """--model (when given) and, for a model with the fit prior, --face-model."""
    weights = getattr(args, "model", None)
    if not weights:
        return []
    return ["--model", weights] + (["--face-model", args.face_model] if takes_fit_prior(weights) else [])


def command_infer(args):
    facetool = find_facetool(args.facetool)
    photos = eval_photos(args.data)
    pred = os.path.join(args.cache, "pred")
    name = getattr(args, "name", None) or "infer"
    model = model_options(args) + shlex.split(getattr(args, "infer_args", None) or "")
    variants = [(name, [])]
    # Stretched crops have no landmarks, so a model with the fit prior cannot take them.
    if not takes_fit_prior(getattr(args, "model", None)):
        variants.append((name + "-aligned", ["--aligned", "--stretch"]))
    for label, extra in variants:
        out = os.path.join(pred, label)
        make_clean(out)
        print(f"facetool infer {' '.join(model + extra)} on {len(photos)} photos -> {out}", flush=True)
        run_facetool([facetool, "infer", *model, *extra, *[p for _, _, p in photos], "-o", out],
                     os.path.join(pred, label + ".log"))
    run_padded(args, photos, [facetool, "infer", *model], "photo.exr", os.path.join(pred, name + "-padded"))
    # Landmarks per subject for the template's alignment: the photos lit near the camera axis
    # (kept from an earlier run: they do not depend on the model).
    out = os.path.join(args.cache, "landmarks")
    if os.path.isdir(out) and os.listdir(out):
        return
    make_clean(out)
    paths = [p for s in subjects(args.data) for p in landmark_photos(args.data, s)]
    print(f"facetool infer on {len(paths)} near-frontally lit photos for landmarks -> {out}", flush=True)
    run_facetool([facetool, "infer", "--no-contact-sheet", *paths, "-o", out],
                 os.path.join(args.cache, "landmarks.log"))


def make_clean(*folders):
    """Empties (or creates) each folder."""
    for d in folders:
        if os.path.isdir(d):
            shutil.rmtree(d)
        os.makedirs(d)


def srgb_encode(linear):
    """0..255 linear camera values as 0..255 sRGB-encoded values (the IEC 61966-2-1 curve)."""
    x = np.clip(linear / 255.0, 0.0, 1.0)
    return 255.0 * np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def srgb_decode(encoded):
    """0..255 sRGB-encoded values back to 0..255 linear values."""
    x = np.clip(encoded / 255.0, 0.0, 1.0)
    return 255.0 * np.where(x <= 0.04045, x / 12.92, np.power((x + 0.055) / 1.055, 2.4))


def padded_photos(args, photos, srgb=False):
    """The given photos ([(subject, stem, path)], any of the set's) padded by a quarter of their
    width on every side with their mean grey, as 8-bit PNGs in CACHE/padded-photos/<stem>.png:
    the crops are so tight that dlib's HOG detector misses most faces; with a margin it finds
    more (by half the width: fewer; repeated edge pixels or black: fewer still). Yale B's values
    are linear in the light (photometric stereo fits them as they are); facetool reads an 8-bit
    PNG as sRGB, as a camera writes it, so with `srgb` the values are sRGB-encoded first (in
    CACHE/padded-photos-srgb/), and facetool then sees the linear light: the light benchmark
    needs this (its shading is the light's); the normal benchmark keeps the raw values of its
    published figures. Returns {stem: (path, pad, (h, w))} in the photos' order."""
    folder = os.path.join(args.cache, "padded-photos-srgb" if srgb else "padded-photos")
    os.makedirs(folder, exist_ok=True)
    out = {}
    for _, stem, path in photos:
        img = read_pgm(path)
        pad = img.shape[1] // 4
        padded = os.path.join(folder, stem + ".png")
        values = np.pad(img, pad, constant_values=float(img.mean()))
        write_png8(padded, srgb_encode(values) if srgb else values)
        out[stem] = (padded, pad, img.shape)
    return out


def run_padded(args, photos, command, result_name, out):
    """Runs `command PADDED... -o OUT-full` on the padded photos and cuts each result's normals
    (`result_name` in its folder) back to the photo's frame as OUT/<stem>/normal.exr."""
    padded = padded_photos(args, photos)
    full = out + "-full"
    make_clean(full, out)
    print(f"{os.path.basename(command[0])} {' '.join(command[1:])} on the {len(photos)} photos "
          f"padded by a quarter of their width -> {out}", flush=True)
    run_facetool([*command, *[v[0] for v in padded.values()], "-o", full], out + ".log")
    for stem, (_, pad, (h, w)) in padded.items():
        path = os.path.join(full, stem, result_name)
        if not os.path.exists(path):
            continue
        n, valid = read_normal_prediction(path)
        n = np.where(valid[:, :, None], n, 0.0)[pad:pad + h, pad:pad + w]
        os.makedirs(os.path.join(out, stem))
        write_exr(os.path.join(out, stem, "normal.exr"), n, ("R", "G", "B"))


# Relighting: the frontal photo relit to each of these lights, against the real photo under it.
RELIGHT_TARGETS = [(25, 0), (-25, 0)]


def relight_yaw(azimuth_deg):
    """The yaw (degrees) of `facetool relight --rotate` that turns a light on the camera axis to
    the strobe at this azimuth (elevation 0): facetool's Ry(yaw) turns +Z towards +X for a
    positive yaw (right-hand rule, apps/facetool/commands/light_rotation.h)."""
    return AZIMUTH_SIGN * azimuth_deg


def read_grey(path):
    """An 8-bit image file as H x W float32 0..255, its channels averaged."""
    pixels, _ = read_exr_channels(path)
    return pixels[:, :, :3].mean(axis=2) * 255.0 if pixels.shape[2] >= 3 else pixels[:, :, 0] * 255.0


def command_relight(args):
    """`facetool relight` of each subject's frontal photo to the +-25 degree lights, two ways:
    the light estimated on the target photo (--light-from TARGET) and the known direction (the
    light estimated on the frontal photo turned by the strobes' azimuth difference about the
    vertical axis, --rotate); PSNR against the real target photo in the PS reliability mask,
    beside the unchanged frontal photo. Runs on the padded photos (as infer-padded; the tight
    crops defeat the detector) and cuts the results back."""
    facetool = find_facetool(args.facetool)
    photos = eval_photos(args.data)
    padded = padded_photos(args, photos)
    name = args.name or "relight"
    model = model_options(args)
    out = os.path.join(args.cache, "relight", name)
    make_clean(out)
    rows = {"unchanged frontal photo": [], f"{name}, light from the target photo": [],
            f"{name}, known direction": []}
    missing = 0
    path_of = {stem: path for _, stem, path in photos}
    for s in subjects(args.data):
        source = eval_stem(s, 0, 0)
        ps_folder = os.path.join(args.cache, "ps", s)
        if source not in padded or not os.path.exists(os.path.join(ps_folder, "reliable.exr")):
            continue
        mask = read_exr_channels(os.path.join(ps_folder, "reliable.exr"))[0][:, :, 0] > 0.5
        src_path, pad, (h, w) = padded[source]
        frontal = read_pgm(path_of[source])
        for a, e in RELIGHT_TARGETS:
            target = eval_stem(s, a, e)
            if target not in padded:
                continue
            truth = read_pgm(path_of[target])

            def psnr(img):
                d = (img[mask] - truth[mask]) / 255.0
                return 10 * math.log10(1.0 / max(float(np.mean(d * d)), 1e-12))

            rows["unchanged frontal photo"].append(psnr(frontal))
            turn = f"--rotate={relight_yaw(a):g},0,0"
            for label, extra in ((f"{name}, light from the target photo", ["--light-from", padded[target][0]]),
                                 (f"{name}, known direction", ["--light-from", src_path, turn])):
                folder = os.path.join(out, f"{target}-{'target' if 'target' in label else 'known'}")
                run_facetool([facetool, "relight", *model, src_path, *extra, "-o", folder], folder + ".log")
                relit = os.path.join(folder, source, "relit.png")
                if not os.path.exists(relit):
                    missing += 1
                    continue
                rows[label].append(psnr(read_grey(relit)[pad:pad + h, pad:pad + w]))
    lines = [f"Relighting on yaleb-dev: each subject's frontal photo relit to the {len(RELIGHT_TARGETS)} "
             f"lights at azimuth {', '.join(f'{a:+d}' for a, _ in RELIGHT_TARGETS)} degrees; PSNR (dB, 8-bit grey "
             f"values, peak 255) against the real photo under that light, in the PS reliability mask"
             + (f"; {missing} relit photo(s) missing (no face found)" if missing else ""), "",
             "| method | pairs | PSNR mean ± std (dB) |", "| --- | --- | --- |"]
    for label, values in rows.items():
        v = np.array(values)
        lines.append(f"| {label} | {len(v)} | " + (f"{v.mean():.2f} ± {v.std():.2f} |" if len(v) else "– |"))
    text = "\n".join(lines)
    print(text)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(text + "\n")


# ---------------------------------------------------------------------------- the light benchmark

# `light`: the strobes within this angle of the camera axis (degrees) are scored.
LIGHT_MAX_ANGLE = 90.0
# Groups of the strobe's angle from the camera axis (degrees; the upper bound belongs to the group).
LIGHT_GROUPS = [(0, 25), (25, 50), (50, 75), (75, 90)]
# The frontal photo relit to these strobes (azimuth, elevation), those that exist.
LIGHT_RELIGHT_TARGETS = [(50, 0), (-50, 0), (70, 0), (-70, 0), (35, 40), (-35, 40), (0, 45)]
RELIGHT_GROUPS = [("±50", lambda a, e: e == 0 and abs(a) == 50),
                  ("±70", lambda a, e: e == 0 and abs(a) == 70),
                  ("elevated", lambda a, e: is_elevated(a, e))]
# The plain ratio relight of the numpy baselines: S = RATIO_AMBIENT + max(n.l, 0), the source's
# S bounded below by RATIO_FLOOR (it only binds where n.l < RATIO_FLOOR - RATIO_AMBIENT).
RATIO_AMBIENT = 0.05
RATIO_FLOOR = 0.1
FRONTAL = (0, 0)


def strobe_of(stem):
    """(azimuth, elevation) in degrees of a photo stem such as yaleB01_P00A+050E+00."""
    m = NAME_RE.match(stem + ".pgm")
    if not m:
        fail(f"{stem}: not a Yale B strobe photo name")
    return int(m.group(2)), int(m.group(3))


def strobe_angle(azimuth, elevation):
    """The strobe's angle from the camera axis, degrees."""
    return math.degrees(math.acos(float(np.clip(light_direction(azimuth, elevation)[2], -1.0, 1.0))))


def is_elevated(azimuth, elevation):
    """The strobes high above the camera and not far to the side ((0,+45), (+-35,+40) ...)."""
    return elevation >= 35 and abs(azimuth) <= 40


def angle_group(angle):
    """The LIGHT_GROUPS label of an angle from the camera axis, or None beyond the last."""
    for low, high in LIGHT_GROUPS:
        if angle <= high + 1e-9:
            return f"{low}-{high}°"
    return None


def light_photos(data):
    """[(subject, stem, path)] of every strobe photo within LIGHT_MAX_ANGLE of the camera axis."""
    out = []
    for s in subjects(data):
        for a, e, path in list_subject(os.path.join(data, s))[0]:
            if strobe_angle(a, e) <= LIGHT_MAX_ANGLE + 1e-9:
                out.append((s, eval_stem(s, a, e), path))
    if not out:
        fail(f"{data}: no strobe photo within {LIGHT_MAX_ANGLE:g} degrees of the camera axis")
    return out


def read_face_light(folder):
    """The light (27 floats, channel-major, the photo's frame: `light_photo_frame`) of the
    largest face (box area) in infer's folder/faces.json and the number of faces, or (None, 0)
    when no face was found."""
    path = os.path.join(folder, "faces.json")
    if not os.path.exists(path):
        return None, 0
    with open(path) as f:
        faces = json.load(f).get("faces", [])
    if not faces:
        return None, 0

    def area(face):
        left, top, right, bottom = face["box"]
        return (right - left) * (bottom - top)

    face = max(faces, key=area)
    light = np.asarray(face.get("light_photo_frame", []), np.float64)
    if light.shape != (27,) or not np.all(np.isfinite(light)):
        fail(f"{path}: the face's light_photo_frame is not 27 finite numbers")
    return light, len(faces)


def light_band1(light):
    """(direction, |L1| / L0) of a 27-float light: its first band averaged over the colours as
    (x, y, z) = (L3, L1, L2), normalised (None when zero), and the norm of that colour-averaged
    vector over the colour-averaged L0 (one distant light: sqrt(3); nan when L0 <= 0)."""
    grey = np.asarray(light, np.float64).reshape(3, 9).mean(0)
    v = np.array([grey[3], grey[1], grey[2]])
    norm = float(np.linalg.norm(v))
    ratio = norm / grey[0] if grey[0] > 0 else float("nan")
    return (v / norm if norm > 0 else None), ratio


def read_decomposition(folder, pad, shape):
    """From infer's folder/photo.exr, cut back to the unpadded photo (pad pixels each side,
    shape (h, w)): the grey albedo (albedo.R/G/B / A, averaged), the unit normals and the
    coverage (A >= 0.5, valid normals); None when there is no photo.exr."""
    path = os.path.join(folder, "photo.exr")
    if not os.path.exists(path):
        return None
    pixels, names = read_exr_channels(path)
    need = ("A", "albedo.R", "albedo.G", "albedo.B")
    if not all(c in names for c in need):
        fail(f"{path}: expected the channels {', '.join(need)}; found {names}")
    h, w = shape
    alpha = pixels[:, :, names.index("A")]
    albedo = sum(pixels[:, :, names.index(c)] for c in need[1:]) / 3.0 / np.maximum(alpha, 1e-6)
    normal, valid = read_normal_prediction(path)
    cut = (slice(pad, pad + h), slice(pad, pad + w))
    return {"albedo": albedo[cut], "normal": normal[cut], "coverage": (alpha >= 0.5)[cut] & valid[cut]}


def relative_rms(a, b):
    """min over s of ||s a - b|| / ||b|| (a, b: 1-D arrays), nan when either is all zero."""
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    aa, ab, bb = a @ a, a @ b, b @ b
    if aa <= 0 or bb <= 0:
        return float("nan")
    return math.sqrt(max(bb - ab * ab / aa, 0.0) / bb)


def psnr_pair(image, truth):
    """PSNR (dB, peak 255) of image against truth (1-D arrays of 0..255 values): as it is, and
    after the best single gain g = <image, truth> / <image, image>."""
    image, truth = np.asarray(image, np.float64), np.asarray(truth, np.float64)

    def psnr(x):
        return 10 * math.log10(255.0 ** 2 / max(float(np.mean((x - truth) ** 2)), 1e-12))

    gain = float(image @ truth / max(image @ image, 1e-12))
    return psnr(image), psnr(gain * image)


def ratio_relight(photo, normal, target):
    """A plain ratio relight: photo x S_t / max(S_s, RATIO_FLOOR), S = RATIO_AMBIENT +
    max(n.l, 0), the source light on the camera axis and target the strobe's unit direction."""
    s_source = RATIO_AMBIENT + np.maximum(normal[..., 2], 0.0)
    s_target = RATIO_AMBIENT + np.maximum(normal @ np.asarray(target, np.float64), 0.0)
    return photo * s_target / np.maximum(s_source, RATIO_FLOOR)


def relight_has_flag(facetool, flag):
    """Whether `facetool relight --help` lists this option."""
    result = subprocess.run([facetool, "relight", "--help"], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    return re.search(rf"(^|[\s,]){re.escape(flag)}\b", result.stdout) is not None


def run_light_infer(facetool, padded, extra, out, reuse):
    """`facetool infer --no-contact-sheet EXTRA PADDED... -o OUT` (its log OUT.log), unless
    reuse and OUT exists."""
    if reuse and os.path.isdir(out):
        print(f"--reuse: scoring the infer results already in {out}", flush=True)
        return
    make_clean(out)
    command = [facetool, "infer", "--no-contact-sheet", *extra]
    print(f"{' '.join(['facetool', *command[1:]])} on {len(padded)} padded photos -> {out} "
          f"(log {out}.log) ...", flush=True)
    start = time.monotonic()
    run_facetool([*command, *[v[0] for v in padded.values()], "-o", out], out + ".log")
    print(f"infer took {time.monotonic() - start:.0f} s", flush=True)


def light_directions(photos, infer_out):
    """Per photo stem: {azimuth, elevation, angle, faces, error (degrees), ratio (|L1|/L0),
    estimate (the unit direction)}; error, ratio and estimate are None where no face was found."""
    rows = {}
    for _, stem, _ in photos:
        a, e = strobe_of(stem)
        light, faces = read_face_light(os.path.join(infer_out, stem))
        row = {"azimuth": a, "elevation": e, "angle": strobe_angle(a, e), "faces": faces,
               "error": None, "ratio": None, "estimate": None}
        if light is not None:
            direction, ratio = light_band1(light)
            row["ratio"] = ratio
            if direction is not None:
                row["estimate"] = [float(v) for v in direction]
                cos = float(np.clip(direction @ light_direction(a, e), -1.0, 1.0))
                row["error"] = math.degrees(math.acos(cos))
        rows[stem] = row
    return rows


def photo_groups(row):
    """The report groups a photo belongs to: its angle group, and 'elevated' when it is."""
    groups = [angle_group(row["angle"])]
    if is_elevated(row["azimuth"], row["elevation"]):
        groups.append("elevated")
    return groups


def group_order():
    return [f"{low}-{high}°" for low, high in LIGHT_GROUPS] + ["elevated"]


def sign_check(rows):
    """The estimated directions' signs against the convention (x = -sin(az) cos(el): negative
    for a positive azimuth; y = sin(el)), their mean bias in x and y, and the mean estimated
    elevation per strobe elevation. Returns (lines,
    flipped): lines for the report, flipped True when a global sign of x or y looks flipped."""
    def mean_of(axis, pick):
        values = [r["estimate"][axis] for r in rows.values() if r["estimate"] is not None and pick(r)]
        return (float(np.mean(values)), len(values)) if values else (float("nan"), 0)

    lines, flipped = [], False
    for axis, name, plus, minus, expect in (
            (0, "x", lambda r: (r["azimuth"], r["elevation"]) == (50, 0),
             lambda r: (r["azimuth"], r["elevation"]) == (-50, 0), "negative for az +50, positive for az -50"),
            (1, "y", lambda r: (r["azimuth"], r["elevation"]) == (0, 45),
             lambda r: (r["azimuth"], r["elevation"]) == (0, -35), "positive for E +45, negative for E -35")):
        (p, np_), (m, nm) = mean_of(axis, plus), mean_of(axis, minus)
        lines.append(f"sign check {name}: mean estimated {name} {p:+.3f} ({np_} photos) vs {m:+.3f} "
                     f"({nm} photos); the convention wants {expect}")
        truth = np.array([light_direction(r["azimuth"], r["elevation"])[axis] for r in rows.values()
                          if r["estimate"] is not None])
        est = np.array([r["estimate"][axis] for r in rows.values() if r["estimate"] is not None])
        strong = np.abs(truth) >= 0.25
        agree = float(np.mean(np.sign(est[strong]) == np.sign(truth[strong]))) if strong.any() else float("nan")
        lines.append(f"sign check {name}: the estimate's {name} has the strobe's sign in "
                     f"{100 * agree:.0f} % of {int(strong.sum())} found photos with |true {name}| >= 0.25")
        lines.append(f"bias {name}: mean estimated - true {name} {np.mean(est - truth):+.3f} over "
                     f"{len(est)} found photos")
        wrong = (axis == 0 and p > 0 > m) or (axis == 1 and p < 0 < m)
        if wrong or agree < 0.25:
            flipped = True
            lines.append(f"!!! WARNING: the estimated light's {name} SIGN LOOKS FLIPPED against the "
                         f"convention (docs: x = -sin(az) cos(el), y = sin(el)); not corrected here !!!")
    by_elevation = {}
    for r in rows.values():
        if r["estimate"] is not None:
            by_elevation.setdefault(r["elevation"], []).append(math.degrees(math.asin(np.clip(r["estimate"][1], -1, 1))))
    lines.append("mean estimated elevation (°) by the strobe's elevation: " + ", ".join(
        f"{e:+d}: {np.mean(v):+.0f} ({len(v)})" for e, v in sorted(by_elevation.items())))
    return lines, flipped


def direction_table(rows):
    """Markdown lines: per group the direction error (mean, median), mean |L1|/L0, found/total."""
    lines = ["| strobes (angle from the camera axis) | found / photos | direction error mean (°) "
             "| median (°) | mean \\|L1\\|/L0 |", "| --- | --- | --- | --- | --- |"]
    for group in group_order() + ["all"]:
        members = [r for r in rows.values() if group == "all" or group in photo_groups(r)]
        found = [r for r in members if r["error"] is not None]
        errors = np.array([r["error"] for r in found])
        ratios = np.array([r["ratio"] for r in members if r["ratio"] is not None])
        cells = ([f"{errors.mean():.1f}", f"{np.median(errors):.1f}"] if errors.size else ["–", "–"])
        cells.append(f"{np.nanmean(ratios):.2f}" if ratios.size and np.isfinite(ratios).any() else "–")
        lines.append(f"| {group} | {len(found)} / {len(members)} | " + " | ".join(cells) + " |")
    return lines


def albedo_scores(photos, padded, infer_out, cache):
    """Per strobe photo (not the frontal one) of a subject whose frontal photo and PS exist: the
    relative RMS after the best scale (relative_rms) of its facetool albedo against the frontal
    photo's and against the PS albedo, and of the raw photo against the raw frontal photo and
    against the PS albedo, all inside the PS reliability mask & both photos' coverage. Returns
    ({stem: scores or None where no face}, {subject: frontal albedo vs PS albedo})."""
    scores, frontal_vs_ps = {}, {}
    by_subject = {}
    for s, stem, path in photos:
        by_subject.setdefault(s, []).append((stem, path))
    for s, items in by_subject.items():
        ps = os.path.join(cache, "ps", s)
        front_stem = eval_stem(s, *FRONTAL)
        paths = dict(items)
        if front_stem not in paths or not os.path.exists(os.path.join(ps, "albedo.exr")):
            continue
        reliable = read_exr_channels(os.path.join(ps, "reliable.exr"))[0][:, :, 0] > 0.5
        ps_albedo = read_exr_channels(os.path.join(ps, "albedo.exr"))[0][:, :, 0]
        _, pad, shape = padded[front_stem]
        front = read_decomposition(os.path.join(infer_out, front_stem), pad, shape)
        front_raw = read_pgm(paths[front_stem])
        if front is None:
            continue
        base = reliable & front["coverage"]
        frontal_vs_ps[s] = relative_rms(front["albedo"][base], ps_albedo[base])
        for stem, path in items:
            if stem == front_stem:
                continue
            got = read_decomposition(os.path.join(infer_out, stem), *padded[stem][1:])
            if got is None:
                scores[stem] = None
                continue
            mask = base & got["coverage"]
            raw = read_pgm(path)
            scores[stem] = {"pixels": int(mask.sum()),
                            "vs_frontal": relative_rms(got["albedo"][mask], front["albedo"][mask]),
                            "vs_ps": relative_rms(got["albedo"][mask], ps_albedo[mask]),
                            "raw_vs_frontal": relative_rms(raw[mask], front_raw[mask]),
                            "raw_vs_ps": relative_rms(raw[mask], ps_albedo[mask])}
    return scores, frontal_vs_ps


def albedo_table(scores, rows):
    """Markdown lines: mean relative RMS per group (and the +-50 degree strobes at elevation 0)."""
    keys = ("vs_frontal", "vs_ps", "raw_vs_frontal", "raw_vs_ps")
    lines = ["| strobes | found / photos | facetool albedo vs frontal photo's | vs PS albedo | "
             "baseline: raw photo vs raw frontal photo | raw photo vs PS albedo |",
             "| --- | --- | --- | --- | --- | --- |"]
    groups = group_order() + ["±50° (E 0)", "all"]
    for group in groups:
        stems = [stem for stem in scores if group == "all" or group in photo_groups(rows[stem])
                 or (group == "±50° (E 0)" and (abs(rows[stem]["azimuth"]), rows[stem]["elevation"]) == (50, 0))]
        found = [scores[stem] for stem in stems if scores[stem] is not None and scores[stem]["pixels"] > 0]
        cells = [f"{np.nanmean([f[k] for f in found]):.3f}" if found else "–" for k in keys]
        lines.append(f"| {group} | {len(found)} / {len(stems)} | " + " | ".join(cells) + " |")
    return lines


def run_light_relights(facetool, subject_names, padded, out, extra, no_visibility, reuse):
    """`facetool relight PADDED_FRONTAL --light-from PADDED_TARGET [--no-visibility] EXTRA -o
    OUT/<target stem>` for each subject and LIGHT_RELIGHT_TARGETS photo that exists (skipped
    with reuse when its relit.png is there). Returns [(subject, target stem)]."""
    pairs = [(s, eval_stem(s, a, e)) for s in subject_names for a, e in LIGHT_RELIGHT_TARGETS
             if eval_stem(s, *FRONTAL) in padded and eval_stem(s, a, e) in padded]
    os.makedirs(out, exist_ok=True)
    start = time.monotonic()
    for k, (s, target) in enumerate(pairs):
        folder = os.path.join(out, target)
        source = padded[eval_stem(s, *FRONTAL)][0]
        if reuse and os.path.isdir(folder):
            continue
        make_clean(folder)
        print(f"[{k + 1}/{len(pairs)}] facetool relight {os.path.basename(source)} --light-from "
              f"{target}.png", flush=True)
        run_facetool([facetool, "relight", source, "--light-from", padded[target][0],
                      *(["--no-visibility"] if no_visibility else []), *extra, "-o", folder],
                     folder + ".log")
    print(f"relight: {len(pairs)} pairs, {time.monotonic() - start:.0f} s", flush=True)
    return pairs


def relight_scores(pairs, photos, padded, infer_out, relight_out, cache):
    """Per (subject, target) pair: PSNR (raw, after the best gain) against the real target photo
    inside the PS reliability mask & the frontal result's coverage of: facetool relight (and
    without visibility when it was written), the ratio relight with facetool's own normals and
    the true directions, the same with the PS normals, and the unchanged frontal photo. Pairs
    without a frontal decomposition are left out; a missing facetool result is None."""
    path_of = {stem: path for _, stem, path in photos}
    scores = {}
    for s, target in pairs:
        front_stem = eval_stem(s, *FRONTAL)
        _, pad, shape = padded[front_stem]
        front = read_decomposition(os.path.join(infer_out, front_stem), pad, shape)
        ps = os.path.join(cache, "ps", s)
        if front is None or not os.path.exists(os.path.join(ps, "normal.exr")):
            continue
        reliable = read_exr_channels(os.path.join(ps, "reliable.exr"))[0][:, :, 0] > 0.5
        ps_normal = read_exr_channels(os.path.join(ps, "normal.exr"))[0][:, :, :3]
        mask = reliable & front["coverage"]
        frontal, truth = read_pgm(path_of[front_stem]), read_pgm(path_of[target])
        direction = light_direction(*strobe_of(target))
        row = {"own normals, true direction": psnr_pair(ratio_relight(frontal, front["normal"], direction)[mask], truth[mask]),
               "PS normals, true direction": psnr_pair(ratio_relight(frontal, ps_normal, direction)[mask], truth[mask]),
               "unchanged frontal photo": psnr_pair(frontal[mask], truth[mask])}
        for label, name in (("facetool relight --light-from target", "relit.png"),
                            ("facetool relight, no visibility", "relit_no_visibility.png")):
            path = os.path.join(relight_out, target, front_stem, name)
            # relit.png is sRGB-encoded; the photos it is scored against are linear
            row[label] = (psnr_pair(srgb_decode(read_grey(path))[pad:pad + shape[0], pad:pad + shape[1]][mask],
                                    truth[mask])
                          if os.path.exists(path) else None)
        scores[target] = row
    return scores


def relight_table(scores):
    """Markdown lines: mean PSNR (raw / after the best gain) per method and target group, over
    the pairs where facetool relight gave a result; and how often visibility helped."""
    methods = ["facetool relight --light-from target", "facetool relight, no visibility",
               "own normals, true direction", "PS normals, true direction", "unchanged frontal photo"]
    done = {t: r for t, r in scores.items() if r["facetool relight --light-from target"] is not None}
    groups = [(label, [t for t in done if pick(*strobe_of(t))]) for label, pick in RELIGHT_GROUPS]
    groups.append(("all", list(done)))
    lines = ["| method | " + " | ".join(f"{g} ({len(ts)} pairs)" for g, ts in groups) + " |",
             "| --- |" + " --- |" * len(groups)]
    for method in methods:
        cells = []
        for _, ts in groups:
            values = [done[t][method] for t in ts if done[t][method] is not None]
            cells.append(f"{np.mean([v[0] for v in values]):.2f} / {np.mean([v[1] for v in values]):.2f}"
                         if values else "–")
        lines.append(f"| {method} | " + " | ".join(cells) + " |")
    both = [r for r in done.values() if r["facetool relight, no visibility"] is not None]
    if both:
        raw = np.mean([r["facetool relight --light-from target"][0] > r["facetool relight, no visibility"][0]
                       for r in both])
        gain = np.mean([r["facetool relight --light-from target"][1] > r["facetool relight, no visibility"][1]
                        for r in both])
        lines += ["", f"Visibility helped (higher PSNR with it than without) in {100 * raw:.0f} % of "
                      f"{len(both)} pairs raw, {100 * gain:.0f} % after the best gain."]
    return lines


def write_markdown(path, text, append=False):
    with open(path, "a" if append else "w") as f:
        f.write(("\n" if append else "") + text + "\n")


def command_light(args, append_markdown=False):
    """Scores the light facetool estimates on the strobe photos within LIGHT_MAX_ANGLE of the
    camera axis (one `infer --no-contact-sheet` run on all of them, padded): the direction of the
    first SH band against the strobe's, |L1|/L0, the albedo's consistency across strobes, and
    relighting the frontal photo to LIGHT_RELIGHT_TARGETS (facetool relight --light-from the
    target photo, against ratio relights with the true directions). Results in
    CACHE/light/NAME (results.json, the infer and relight outputs)."""
    facetool = find_facetool(getattr(args, "facetool", None))
    name = getattr(args, "name", None) or "light"
    reuse = getattr(args, "reuse", False)
    infer_extra = shlex.split(getattr(args, "infer_args", None) or "")
    relight_args = getattr(args, "relight_args", None)
    relight_extra = infer_extra if relight_args is None else shlex.split(relight_args)
    photos = light_photos(args.data)
    names = sorted({s for s, _, _ in photos})
    missing_ps = [s for s in names if not os.path.exists(os.path.join(args.cache, "ps", s, "reliable.exr"))]
    if missing_ps:
        fail(f"no PS results for {', '.join(missing_ps)} in {os.path.join(args.cache, 'ps')}: run `ps` first")
    out = os.path.join(args.cache, "light", name)
    os.makedirs(out, exist_ok=True)
    print(f"light: {len(photos)} photos ({len(names)} subjects, strobes within {LIGHT_MAX_ANGLE:g} "
          f"degrees of the camera axis) -> {out}", flush=True)
    padded = padded_photos(args, photos, srgb=True)
    infer_out = os.path.join(out, "infer")
    run_light_infer(facetool, padded, infer_extra, infer_out, reuse)
    rows = light_directions(photos, infer_out)
    no_visibility = relight_has_flag(facetool, "--no-visibility")
    pairs = run_light_relights(facetool, names, padded, os.path.join(out, "relight"), relight_extra,
                               no_visibility, reuse)
    print("scoring ...", flush=True)
    albedo, frontal_vs_ps = albedo_scores(photos, padded, infer_out, args.cache)
    relit = relight_scores(pairs, photos, padded, infer_out, os.path.join(out, "relight"), args.cache)
    signs, flipped = sign_check(rows)
    multi = sum(1 for r in rows.values() if r["faces"] > 1)
    found = sum(1 for r in rows.values() if r["faces"] > 0)
    elevated = sorted({(r["azimuth"], r["elevation"]) for r in rows.values()
                       if is_elevated(r["azimuth"], r["elevation"])})
    groups = ", ".join(f"{lo}-{hi}" for lo, hi in LIGHT_GROUPS)
    command = " ".join(["facetool infer --no-contact-sheet", *infer_extra])
    lines = [f"## Light on yaleb-dev: {name}", "",
             f"`{command}` on {len(photos)} strobe photos ({len(names)} subjects, every strobe within "
             f"{LIGHT_MAX_ANGLE:g}° of the camera axis), padded by a quarter of their width; a face in "
             f"{found} ({multi} with more than one: the largest box's light scored).", "",
             *signs, *(["", "**THE LIGHT'S SIGN CONVENTION LOOKS FLIPPED: see above.**"] if flipped else []), "",
             "### Light direction (the first SH band averaged over colours, (x, y, z) = (L3, L1, L2)) "
             "against the strobe", "",
             f"Groups by the strobe's angle from the camera axis ({groups}°, upper bound included); "
             f"'elevated': elevation ≥ 35° and |azimuth| ≤ 40°: "
             + ", ".join(f"({a:+d},{e:+d})" for a, e in elevated) + ". One distant light has "
             "\\|L1\\|/L0 = 1.73.", "",
             *direction_table(rows), "",
             "### Albedo consistency across strobes", "",
             "Relative RMS after the best single scale (min_s \\|\\|s a - b\\|\\| / \\|\\|b\\|\\|), grey "
             "albedo (albedo.R/G/B / A where A ≥ 0.5), inside the PS reliability mask & the strobe "
             "photo's & the frontal photo's coverage; mean over photos (the frontal photo itself "
             "left out). facetool's frontal albedo against the PS albedo: "
             + (f"{np.mean(list(frontal_vs_ps.values())):.3f} (mean of {len(frontal_vs_ps)} subjects)."
                if frontal_vs_ps else "–."), "",
             *albedo_table(albedo, rows), "",
             "### Relighting the frontal photo", "",
             "PSNR (dB, 8-bit grey, peak 255) against the real photo under the target strobe, inside the "
             "PS reliability mask & the frontal result's coverage, mean over pairs, raw / after the "
             "best single gain. Targets: "
             + ", ".join(f"({a:+d},{e:+d})" for a, e in LIGHT_RELIGHT_TARGETS)
             + f"; the pairs where facetool relight gave a result (of {len(relit)} scored). Ratio "
             f"relights: frontal x S_t / max(S_s, {RATIO_FLOOR:g}), S = {RATIO_AMBIENT:g} + "
             "max(n.l, 0), source light (0,0,1), the true strobe direction"
             + ("" if no_visibility else "; this facetool's relight has no --no-visibility") + ".", "",
             *relight_table(relit)]
    text = "\n".join(lines)
    print(text)
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump({"directions": rows, "albedo": albedo, "frontal_albedo_vs_ps": frontal_vs_ps,
                   "relight": relit, "sign_flipped": flipped}, f, indent=1)
    markdown = getattr(args, "markdown", None)
    if markdown:
        write_markdown(markdown, text, append_markdown)


# `fit`'s options for this set unless --fit-args gives the same option: Yale B's camera is far
# from the face, so the field of view over these tight crops is narrow (chosen on this set:
# docs/benchmarks.md); the benchmark reads only normal.exr, so no visibility or contact sheets.
YALEB_FIT_ARGS = {"--fov": ["--fov", "10"], "--no-visibility": ["--no-visibility"],
                  "--no-contact-sheet": ["--no-contact-sheet"]}


def fit_command(args):
    """`BIN fit --face-model DIR` with YALEB_FIT_ARGS, less those --fit-args overrides, then
    --fit-args."""
    extra = (args.fit_args or "").split()
    given = {a.split("=")[0] for a in extra if a.startswith("--")}
    defaults = [v for k, vs in YALEB_FIT_ARGS.items() if k not in given for v in vs]
    return [args.fit_bin, "fit", "--face-model", args.face_model, *defaults, *extra]


def command_fit(args):
    if not args.fit_bin:
        fail("fit needs --fit-bin BIN (a facetool with the `fit` command)")
    if not os.path.isdir(args.face_model):
        fail(f"no ICT-FaceKit model folder at {args.face_model} (pass --face-model DIR)")
    photos = eval_photos(args.data)
    command = fit_command(args)
    out = os.path.join(args.cache, "pred", "fit")
    make_clean(out)
    print(f"{' '.join(command[1:])} on {len(photos)} photos -> {out}", flush=True)
    run_facetool([*command, *[p for _, _, p in photos], "-o", out], out + ".log")
    run_padded(args, photos, command, "normal.exr", os.path.join(args.cache, "pred", "fit-padded"))
    # Each subject's five photos as one still head (`fit --still-head`): the head does not move
    # between the strobes, so one pose, identity and expression fit all five photos' landmarks.
    # This has what the template has (landmarks from several photos of the head); the fit above
    # has one photo's.
    out = os.path.join(args.cache, "pred", "fit-still-head")
    make_clean(out)
    subjects = sorted({s for s, _, _ in photos})
    print(f"{' '.join(command[1:])} --still-head on each subject's {len(photos) // len(subjects)} photos -> {out}",
          flush=True)
    for s in subjects:
        run_facetool([*command, "--still-head", *[p for t, _, p in photos if t == s], "-o", out],
                     f"{out}-{s}.log")


# ------------------------------------------------------------------------------ the template

def subject_landmarks(cache, s):
    """Median 68 landmarks (photo pixels) of subject s over its detected landmark photos, or
    None when no photo of it was detected."""
    folder = os.path.join(cache, "landmarks")
    found = []
    if os.path.isdir(folder):
        for name in sorted(os.listdir(folder)):
            path = os.path.join(folder, name, "faces.json")
            if name.startswith(s + "_") and os.path.exists(path):
                with open(path) as f:
                    faces = json.load(f).get("faces", [])
                if faces:
                    pts = np.asarray(faces[0]["landmarks"], np.float64).reshape(-1, 2)
                    if pts.shape == (68, 2):
                        found.append(pts)
    return np.median(np.stack(found), 0) if found else None


def similarity(src, dst):
    """Least-squares similarity (scale, rotation, translation; no reflection) taking the points
    src to dst, as a 2 x 3 matrix on (x, y, 1) (Umeyama's closed form)."""
    mu_s, mu_d = src.mean(0), dst.mean(0)
    a, b = src - mu_s, dst - mu_d
    cov = b.T @ a / len(src)
    u, d, vt = np.linalg.svd(cov)
    sign = np.diag([1.0, np.sign(np.linalg.det(u @ vt))])
    rot = u @ sign @ vt
    scale = np.trace(np.diag(d) @ sign) / (a ** 2).sum(1).mean()
    m = np.zeros((2, 3))
    m[:, :2] = scale * rot
    m[:, 2] = mu_d - scale * rot @ mu_s
    return m


def warp_normals(normal, valid, m, shape):
    """Samples a source normal map at m @ (x, y, 1) of every target pixel (bilinear over valid
    pixels) and turns the normals by the map's rotation (so they stay in the target's camera
    frame). Returns (normals, valid) of the target's shape."""
    h, w = shape
    ys, xs = np.mgrid[0:h, 0:w].astype(np.float64)
    sx = m[0, 0] * xs + m[0, 1] * ys + m[0, 2]
    sy = m[1, 0] * xs + m[1, 1] * ys + m[1, 2]
    x0, y0 = np.floor(sx).astype(int), np.floor(sy).astype(int)
    fx, fy = sx - x0, sy - y0
    acc = np.zeros((h, w, 3))
    wsum = np.zeros((h, w))
    for dy, dx, wt in ((0, 0, (1 - fx) * (1 - fy)), (0, 1, fx * (1 - fy)),
                       (1, 0, (1 - fx) * fy), (1, 1, fx * fy)):
        yy, xx = y0 + dy, x0 + dx
        inside = (yy >= 0) & (yy < normal.shape[0]) & (xx >= 0) & (xx < normal.shape[1])
        yc, xc = np.clip(yy, 0, normal.shape[0] - 1), np.clip(xx, 0, normal.shape[1] - 1)
        ok = inside & valid[yc, xc]
        acc += np.where(ok, wt, 0.0)[:, :, None] * normal[yc, xc]
        wsum += np.where(ok, wt, 0.0)
    out_valid = wsum >= 0.5
    n = acc / np.maximum(wsum, 1e-12)[:, :, None]
    # The target-to-source map turns image (x right, y down) vectors by phi = atan2(m10, m00);
    # source-to-target turns them by -phi, which in the camera frame (y up) is +phi.
    phi = math.atan2(m[1, 0], m[0, 0])
    c, s_ = math.cos(phi), math.sin(phi)
    n = np.stack([c * n[..., 0] - s_ * n[..., 1], s_ * n[..., 0] + c * n[..., 1], n[..., 2]], -1)
    length = np.linalg.norm(n, axis=-1)
    out_valid &= length > 1e-6
    return np.where(out_valid[:, :, None], n / np.maximum(length, 1e-12)[:, :, None], 0.0), out_valid


def photo_landmarks(folder, stem):
    """The 68 landmarks (photo pixels) of one photo's largest face as a prediction folder
    recorded them (`fit`'s fit.json or `infer`'s faces.json), or None."""
    for name, key in (("fit.json", None), ("faces.json", "faces")):
        path = os.path.join(folder, stem, name)
        if not os.path.exists(path):
            continue
        with open(path) as f:
            doc = json.load(f)
        face = doc if key is None else (doc.get(key) or [None])[0]
        if face and "landmarks" in face:
            pts = np.asarray(face["landmarks"], np.float64).reshape(-1, 2)
            if pts.shape == (68, 2):
                return pts
    return None


INNER = slice(17, 68)    # the 51 inner landmarks (brows, eyes, nose, mouth); the jaw slides


def leave_one_out_template(target, refs, landmarks, aligned=True, min_subjects=3):
    """Mean of the other subjects' PS normals in the target's frame: each warped by the
    similarity of its inner landmarks to the target's (aligned=True and both have landmarks;
    otherwise as cropped), averaged, renormalised; valid where min_subjects contributed."""
    h, w = refs[target][0].shape[:2]
    acc = np.zeros((h, w, 3))
    count = np.zeros((h, w))
    for s, (normal, valid) in refs.items():
        if s == target:
            continue
        if aligned and landmarks.get(target) is not None and landmarks.get(s) is not None:
            m = similarity(landmarks[target][INNER], landmarks[s][INNER])
        else:
            m = np.array([[1.0, 0, 0], [0, 1.0, 0]])
        n, v = warp_normals(normal, valid, m, (h, w))
        acc += n * v[:, :, None]
        count += v
    n = acc / np.maximum(np.linalg.norm(acc, axis=-1), 1e-12)[:, :, None]
    valid = count >= min_subjects
    return np.where(valid[:, :, None], n, 0.0), valid


# --------------------------------------------------------------------------------- scoring

def angular_error_deg(pred, truth):
    """Per-pixel angle in degrees between two H x W x 3 (or N x 3) normal arrays (both
    normalised here)."""
    p = pred / np.maximum(np.linalg.norm(pred, axis=-1, keepdims=True), 1e-12)
    t = truth / np.maximum(np.linalg.norm(truth, axis=-1, keepdims=True), 1e-12)
    return np.degrees(np.arccos(np.clip((p * t).sum(-1), -1.0, 1.0)))


def summarise(per_photo, mask_pixels):
    """The paper's Table 1 figures from [angle arrays, one per scored photo]: mean and std over
    photos of the per-photo mean error, and the percentage of all scored pixels under 20, 25
    and 30 degrees; coverage = scored pixels / evaluation-mask pixels of all the photos."""
    scored = [a for a in per_photo if a.size]
    if not scored:
        return {"photos": 0, "coverage": 0.0}
    means = np.array([a.mean() for a in scored])
    pooled = np.concatenate(scored)
    return {
        "photos": len(scored),
        "coverage": float(pooled.size / mask_pixels) if mask_pixels else 0.0,
        "mean": float(means.mean()), "std": float(means.std()),
        "pixel_mean": float(pooled.mean()),
        "under20": float(100 * (pooled < 20).mean()), "under25": float(100 * (pooled < 25).mean()),
        "under30": float(100 * (pooled < 30).mean()),
    }


def find_prediction(folder, stem):
    for name in ("normal.exr", "photo.exr"):
        path = os.path.join(folder, stem, name)
        if os.path.exists(path):
            return path
    return None


def load_prediction(folder, stem, shape):
    """(normals, valid) of one photo from a prediction folder, at the photo's resolution
    (crop-level maps of another size, e.g. `infer --aligned`, are resized bilinearly), or None."""
    path = find_prediction(folder, stem)
    if path is None:
        return None
    n, valid = read_normal_prediction(path)
    if n.shape[:2] != shape:
        h, w = shape
        m = np.array([[n.shape[1] / w, 0, 0.5 * n.shape[1] / w - 0.5],
                      [0, n.shape[0] / h, 0.5 * n.shape[0] / h - 0.5]])
        n, valid = warp_normals(n, valid, m, shape)
    return n, valid


def command_score(args):
    photos = eval_photos(args.data)
    names = sorted({s for s, _, _ in photos})
    refs = {}
    for s in names:
        folder = os.path.join(args.cache, "ps", s)
        if not os.path.exists(os.path.join(folder, "normal.exr")):
            fail(f"no PS normals for {s} in {folder}: run `ps` first")
        n, _ = read_exr_channels(os.path.join(folder, "normal.exr"))
        rel, _ = read_exr_channels(os.path.join(folder, "reliable.exr"))
        refs[s] = (n[:, :, :3], rel[:, :, 0] > 0.5)
    landmarks = {s: subject_landmarks(args.cache, s) for s in names}
    have = [s for s in names if landmarks[s] is not None]
    print(f"landmarks for the template's alignment: {len(have)} of {len(names)} subjects", flush=True)
    templates = {}
    for s in names:
        templates[s] = {"aligned": leave_one_out_template(s, refs, landmarks, True),
                        "as cropped": leave_one_out_template(s, refs, landmarks, False)}
    # The evaluation mask: the PS reliability mask where the aligned leave-one-out template is
    # defined too (>= 3 other subjects reliable there), so both baselines cover all of it.
    masks = {s: refs[s][1] & templates[s]["aligned"][1] for s in names}
    kept = sum(int(masks[s].sum()) for s in names) / max(1, sum(int(refs[s][1].sum()) for s in names))
    print(f"evaluation mask: {100 * kept:.1f} % of the reliability mask (the rest lacks a template)")
    candidates = list(args.pred or [])
    if not candidates:
        pred = os.path.join(args.cache, "pred")
        names_found = sorted(os.listdir(pred)) if os.path.isdir(pred) else []
        for name in names_found:  # every prediction folder (not the padded runs' uncut outputs)
            folder = os.path.join(pred, name)
            if os.path.isdir(folder) and not name.endswith("-full"):
                candidates.append(f"{name}={folder}")
    constant = np.zeros(refs[names[0]][0].shape)
    constant[..., 2] = 1.0
    rows = []       # (label, summary)
    per_light = {}  # label -> {light: summary}

    def score(label, predict):
        """predict(subject, stem) -> (normals, valid) or None; scores all evaluation photos."""
        angles, total, total_found, by_light = [], 0, 0, {}
        for s, stem, _ in photos:
            truth, mask = refs[s][0], masks[s]
            total += int(mask.sum())
            got = predict(s, stem)
            total_found += int(mask.sum()) if got is not None else 0
            sel = mask & got[1] if got is not None else np.zeros_like(mask)
            a = angular_error_deg(got[0][sel], truth[sel]) if got is not None else np.zeros(0)
            angles.append(a)
            light = stem.split("_P00")[1]
            by_light.setdefault(light, ([], [0]))
            by_light[light][0].append(a)
            by_light[light][1][0] += int(mask.sum())
        summary = summarise(angles, total)
        summary["coverage_in_found"] = summary["coverage"] * total / total_found if total_found else 0.0
        rows.append((label, summary))
        per_light[label] = {k: summarise(v[0], v[1][0]) for k, v in sorted(by_light.items())}

    score("constant normal (0,0,1)", lambda s, stem: (constant, np.ones(constant.shape[:2], bool)))
    score("leave-one-out template, landmark-aligned", lambda s, stem: templates[s]["aligned"])
    score("leave-one-out template, as cropped", lambda s, stem: templates[s]["as cropped"])
    predictors = {}
    for spec in candidates:
        label, _, folder = spec.partition("=")
        if not folder:
            label, folder = os.path.basename(os.path.normpath(spec)), spec
        if not os.path.isdir(folder):
            fail(f"--pred {spec}: no such folder")
        cache = {}

        def predict(s, stem, folder=folder, cache=cache):
            if stem not in cache:
                cache[stem] = load_prediction(folder, stem, refs[s][0].shape[:2])
            return cache[stem]

        predictors[label] = predict
    fit = predictors.get("fit")
    # The template a single photo can have: the other subjects' normals aligned by this photo's
    # own landmarks (the ones the fit got), not by the subject's median over its well-lit photos.
    own_templates = {}

    def template_by_own_landmarks(s, stem, folder):
        if stem not in own_templates:
            pts = photo_landmarks(folder, stem)
            own_templates[stem] = None if pts is None else \
                leave_one_out_template(s, refs, {**landmarks, s: pts}, True)
        return own_templates[stem]

    for label, predict in predictors.items():
        score(label, predict)
        if label == "fit":
            folder = dict(spec.partition("=")[::2] for spec in candidates)["fit"]
            score("  template aligned by each photo's own landmarks (the fit's), on the fit's pixels",
                  lambda s, stem: None if template_by_own_landmarks(s, stem, folder) is None
                  or predict(s, stem) is None else
                  (template_by_own_landmarks(s, stem, folder)[0],
                   template_by_own_landmarks(s, stem, folder)[1] & predict(s, stem)[1]))
        # The baselines on exactly the pixels this candidate covers.
        score(f"  constant normal, on {label}'s pixels", lambda s, stem, p=predict:
              None if p(s, stem) is None else (constant, p(s, stem)[1]))
        score(f"  template (aligned), on {label}'s pixels", lambda s, stem, p=predict:
              None if p(s, stem) is None else
              (templates[s]["aligned"][0], templates[s]["aligned"][1] & p(s, stem)[1]))
        # The landmark fit (the `fit` folder) where both it and this candidate have normals: the
        # model goal's "0.8 x the fit's error on the same pixels" (docs/model-card.md).
        if fit is not None and not label.startswith("fit"):
            def on_both(s, stem, p=predict):
                got, f = p(s, stem), fit(s, stem)
                return None if got is None or f is None else (f[0], f[1] & got[1])

            def candidate_on_both(s, stem, p=predict):
                got, f = p(s, stem), fit(s, stem)
                return None if got is None or f is None else (got[0], f[1] & got[1])

            score(f"  {label}, where the fit has normals too", candidate_on_both)
            score(f"  fit, where {label} has normals", on_both)
    lines = [f"{len(photos)} photos ({len(names)} subjects x lights "
             + ", ".join(eval_stem('', a, e).split('_P00')[1] for a, e in EVAL_LIGHTS)
             + f"), scored inside the evaluation mask (the PS reliability mask where the template "
             f"is defined: {100 * kept:.1f} % of it)", "",
             "| normals | photos scored | coverage | in those photos | mean ± std (°) | < 20° | < 25° "
             "| < 30° |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for label, r in rows:
        if r["photos"] == 0:
            lines.append(f"| {label} | 0 | 0 % | – | – | – | – | – |")
            continue
        lines.append(f"| {label} | {r['photos']} | {100 * r['coverage']:.1f} % | "
                     f"{100 * r['coverage_in_found']:.1f} % | "
                     f"{r['mean']:.1f} ± {r['std']:.1f} | {r['under20']:.1f} % | "
                     f"{r['under25']:.1f} % | {r['under30']:.1f} % |")
    order = [eval_stem("", a, e).split("_P00")[1] for a, e in EVAL_LIGHTS]
    lights = [k for k in order if k in next(iter(per_light.values()))]
    lines += ["", "Mean angular error (°) by light (photos scored):", "",
              "| normals | " + " | ".join(lights) + " |", "| --- |" + " --- |" * len(lights)]
    for label, by in per_light.items():
        cells = [f"{by[k]['mean']:.1f} ({by[k]['photos']})" if by[k]["photos"] else "–" for k in lights]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    text = "\n".join(lines)
    print(text)
    with open(os.path.join(args.cache, "results.json"), "w") as f:
        json.dump({"rows": rows, "per_light": per_light}, f, indent=1)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(text + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--data", default=DEFAULT_DATA, help="the yaleb-dev folder")
    parser.add_argument("--cache", default=DEFAULT_CACHE, help="where results go (default build/yaleb)")
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("ps", help="photometric-stereo normals, albedo and reliability masks")
    sub.add_parser("ps-halves", help="the reference's random error: PS from two halves of the strobes compared")
    p = sub.add_parser("infer", help="facetool infer (photo and --aligned) on the evaluation photos")
    p.add_argument("--facetool", help="the facetool program (default: build/bin/facetool)")
    p.add_argument("--model", help="trained weights for infer (default: the shipped model)")
    p.add_argument("--name", help="the prediction folders' name under CACHE/pred (default: infer; "
                                  "then NAME-aligned and NAME-padded)")
    p.add_argument("--face-model", default=DEFAULT_FACE_MODEL,
                   help="the ICT-FaceKit FaceXModel folder, for a model with the fit prior (default: ../shared's)")
    p.add_argument("--infer-args", help="more options for every infer run, one string (e.g. '--face-region hull')")
    p = sub.add_parser("relight", help="relight the frontal photos to the +-25 degree lights; PSNR")
    p.add_argument("--facetool", help="the facetool program (default: build/bin/facetool)")
    p.add_argument("--model", help="trained weights for relight (default: the shipped model)")
    p.add_argument("--name", help="the results' name (default: relight)")
    p.add_argument("--face-model", default=DEFAULT_FACE_MODEL,
                   help="the ICT-FaceKit FaceXModel folder, for a model with the fit prior (default: ../shared's)")
    p.add_argument("--markdown", help="also write the table to this file")
    p = sub.add_parser("light", help="score infer's light on the strobes within 90 degrees: direction, "
                                     "albedo consistency, relighting")
    p.add_argument("--facetool", help="the facetool program (default: build/bin/facetool)")
    p.add_argument("--name", help="the results' folder under CACHE/light (default: light)")
    p.add_argument("--infer-args", help="more options for infer, one string, written with '=' when it starts "
                                        "with a dash (e.g. --infer-args=--no-light-solve)")
    p.add_argument("--relight-args", help="more options for relight, one string (default: --infer-args; "
                                          "give --relight-args= when those are infer's alone)")
    p.add_argument("--reuse", action="store_true",
                   help="score the results already in CACHE/light/NAME (run infer and relight only where missing)")
    p.add_argument("--markdown", help="also write the tables to this file")
    p = sub.add_parser("fit", help="facetool fit on the evaluation photos")
    p.add_argument("--fit-bin", required=True, help="a facetool program with the fit command")
    p.add_argument("--face-model", default=DEFAULT_FACE_MODEL,
                   help="the ICT-FaceKit FaceXModel folder for fit (default: ../shared's)")
    p.add_argument("--fit-args", help="more options for fit, one string (e.g. '--camera orthographic'); each replaces "
                        "the same option of the set's defaults (--fov 10 --no-visibility --no-contact-sheet)")

    p = sub.add_parser("score", help="score the predictions against the PS normals")
    p.add_argument("--pred", action="append", metavar="NAME=DIR",
                   help="a folder of DIR/<photo stem>/normal.exr (or photo.exr); repeatable "
                        "(default: every folder under CACHE/pred)")
    p.add_argument("--markdown", help="also write the tables to this file")
    p = sub.add_parser("run", help="ps, infer, fit (with --fit-bin), score and light")
    p.add_argument("--facetool", help="the facetool program (default: build/bin/facetool)")
    p.add_argument("--fit-bin", help="a facetool program with the fit command")
    p.add_argument("--fit-dir", help="a folder of <photo stem>/normal.exr to score as 'fit'")
    p.add_argument("--face-model", default=DEFAULT_FACE_MODEL,
                   help="the ICT-FaceKit FaceXModel folder for fit (default: ../shared's)")
    p.add_argument("--fit-args", help="more options for fit, one string (e.g. '--camera orthographic'); each replaces "
                        "the same option of the set's defaults (--fov 10 --no-visibility --no-contact-sheet)")

    p.add_argument("--markdown", help="also write the tables to this file (light's appended)")
    args = parser.parse_args()
    if args.command == "ps":
        command_ps(args)
    elif args.command == "ps-halves":
        command_ps_halves(args)
    elif args.command == "infer":
        command_infer(args)
    elif args.command == "fit":
        command_fit(args)
    elif args.command == "relight":
        command_relight(args)
    elif args.command == "score":
        command_score(args)
    elif args.command == "light":
        command_light(args)
    elif args.command == "run":
        command_ps(args)
        command_infer(args)
        args.pred = None
        if args.fit_bin:
            command_fit(args)
        if args.fit_dir:
            args.pred = [f"{n}={os.path.join(args.cache, 'pred', n)}"
                         for n in ("infer", "infer-padded", "infer-aligned")
                         if os.path.isdir(os.path.join(args.cache, "pred", n))]
            args.pred.append(f"fit={args.fit_dir}")
        command_score(args)
        command_light(args, append_markdown=True)


if __name__ == "__main__":
    main()
