#!/usr/bin/env python3
"""Tests of scripts/yaleb_benchmark.py on synthetic data: the PS solver, the light convention, the scorer, the template's warp, reading a photo's landmarks."""
import json
import math
import os
import struct
import sys
import tempfile
import unittest

try:
    import numpy as np
except ImportError:
    print("SKIP: no numpy for python3 (Debian: python3-numpy)")
    sys.exit(77)

sys.dont_write_bytecode = True   # no __pycache__ in the source tree
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import yaleb_benchmark as yb  # noqa: E402


def sphere_scene(size=96, radius=40.0):
    """Closed-form sphere normals (camera frame: x right, y up, z to the viewer) of an
    orthographic sphere centred in a size x size image, the disc mask, and a textured albedo."""
    v, u = np.mgrid[0:size, 0:size].astype(np.float64)
    x, y = (u - (size - 1) / 2) / radius, -(v - (size - 1) / 2) / radius
    r2 = x * x + y * y
    disc = r2 < 1.0
    z = np.sqrt(np.maximum(0.0, 1.0 - r2))
    normal = np.stack([x, y, z], -1) * disc[..., None]
    albedo = 0.55 + 0.35 * np.sin(u / 5.0) * np.cos(v / 7.0)
    return normal, disc, albedo


def yale_like_lights():
    """Strobe directions like Yale B's within 80 degrees of the axis (azimuth, elevation grid)."""
    dirs = []
    for a in (-70, -50, -35, -20, -10, 0, 10, 20, 35, 50, 70):
        for e in (-35, -20, 0, 20, 45):
            d = yb.light_direction(a, e)
            if math.degrees(math.acos(d[2])) <= 80:
                dirs.append(d)
    return np.array(dirs)


def render(normal, disc, albedo, lights, rng, scale=300.0):
    """8-bit photos of a Lambertian scene with attached shadows, a cast shadow (a band that
    the lights from the viewer's right cannot reach), specular outliers, sensor noise,
    quantisation and clipping at 255. Returns (raw, cast-shadow mask per light)."""
    shading = np.maximum(0.0, np.einsum("hwc,kc->khw", normal, lights))
    image = scale * albedo[None] * shading
    h, w = disc.shape
    v, u = np.mgrid[0:h, 0:w]
    band = (u > 0.25 * w) & (u < 0.4 * w) & (v > 0.3 * h) & (v < 0.7 * h)
    cast = (lights[:, 0] > 0.3)[:, None, None] & band[None]
    image = np.where(cast, 0.0, image)
    spikes = rng.random(image.shape) < 0.03
    image = image + spikes * (shading > 0.2) * 80.0
    image = image + rng.normal(0.0, 1.0, image.shape)
    raw = np.clip(np.rint(image), 0, 255) * disc[None]
    return raw.astype(np.float32), cast


class PhotometricStereo(unittest.TestCase):
    def setUp(self):
        self.rng = np.random.default_rng(7)
        self.normal, self.disc, self.albedo = sphere_scene()
        self.lights = yale_like_lights()
        self.raw, self.cast = render(self.normal, self.disc, self.albedo, self.lights, self.rng)

    def test_recovers_sphere_normals_despite_shadows_clipping_and_outliers(self):
        r = yb.solve_photometric_stereo(self.raw, self.raw, self.lights)
        # Judge where the sphere faces the camera well enough for >= MIN_LIGHTS lit samples.
        region = self.disc & (self.normal[..., 2] > 0.35)
        err = yb.angular_error_deg(r["normal"][region], self.normal[region])
        reliable = r["reliable"][region]
        self.assertGreater(reliable.mean(), 0.9)
        self.assertLess(err[reliable].mean(), 1.0)          # degrees
        self.assertLess(np.percentile(err[reliable], 99), 3.0)
        # The scaled normal's length is the albedo times the render scale (300) within 2 %.
        ratio = r["albedo"][region][reliable] / (300.0 * self.albedo[region][reliable])
        self.assertLess(np.abs(np.median(ratio) - 1.0), 0.02)
        # Outside the disc (black background) nothing is reliable.
        self.assertFalse(r["reliable"][~self.disc].any())

    def test_plain_least_squares_fails_on_the_same_scene(self):
        """The scene is hard: least squares over every sample is off by degrees, so the test
        above measures the rejection, not an easy case."""
        k = len(self.lights)
        i_flat = self.raw.reshape(k, -1).astype(np.float64)
        b = np.linalg.lstsq(self.lights, i_flat, rcond=None)[0].T
        region = (self.disc & (self.normal[..., 2] > 0.35)).reshape(-1)
        err = yb.angular_error_deg(b[region], self.normal.reshape(-1, 3)[region])
        self.assertGreater(err.mean(), 3.0)

    def test_pixels_with_too_few_lit_samples_are_unreliable(self):
        raw = self.raw.copy()
        patch = (slice(44, 52), slice(44, 52))              # the sphere's centre
        dark = np.ones(len(self.lights), bool)
        dark[:yb.MIN_LIGHTS - 2] = False                     # lit by MIN_LIGHTS - 2 strobes
        raw[dark, patch[0], patch[1]] = 0.0
        r = yb.solve_photometric_stereo(raw, raw, self.lights)
        self.assertFalse(r["reliable"][patch].any())
        self.assertTrue(r["reliable"][30:40, 30:40].all())

    def test_saturated_samples_are_never_used(self):
        """Expose 2.5x longer: about half of the lit samples clip at 255; the rest still give
        the normals, and no clipped sample counts as an inlier."""
        raw, _ = render(self.normal, self.disc, self.albedo, self.lights, self.rng, scale=750.0)
        r = yb.solve_photometric_stereo(raw, raw, self.lights)
        region = self.disc & (self.normal[..., 2] > 0.35) & r["reliable"]
        clipped = (raw >= yb.SATURATED_DN).sum(0)
        self.assertGreater((clipped[region] >= 10).sum(), 500)
        self.assertTrue((r["lights"] <= (raw < yb.SATURATED_DN).sum(0)).all())
        self.assertLess(yb.angular_error_deg(r["normal"][region], self.normal[region]).mean(), 1.0)


class StrobeHalves(unittest.TestCase):
    def test_halves_split_every_strobe_and_span_the_directions(self):
        lights = yale_like_lights()
        a, b = yb.strobe_halves(lights)
        self.assertEqual(sorted(np.concatenate([a, b]).tolist()), list(range(len(lights))))
        self.assertLessEqual(abs(len(a) - len(b)), 1)
        for half in (a, b):   # lights from both sides and from above and below in each half
            self.assertTrue((lights[half, 0] > 0.3).any() and (lights[half, 0] < -0.3).any())
            self.assertTrue((lights[half, 1] > 0.3).any() and (lights[half, 1] < -0.2).any())

    def test_disagreement_measures_the_noise(self):
        """Lambertian sphere with Gaussian noise only: the halves' disagreement is about twice
        the full solution's error against the closed-form normals, and vanishes without noise."""
        normal, disc, albedo = sphere_scene()
        lights = yale_like_lights()
        clean = 300.0 * albedo[None] * np.maximum(0.0, np.einsum("hwc,kc->khw", normal, lights)) * disc[None]
        angle, mask, _ = yb.halves_disagreement(clean, clean, lights)
        self.assertGreater(mask.sum(), 1000)
        self.assertLess(angle.mean(), 0.05)
        noisy = clean + np.random.default_rng(3).normal(0.0, 6.0, clean.shape) * disc[None]
        angle, mask, _ = yb.halves_disagreement(noisy, noisy, lights)
        full = yb.solve_photometric_stereo(noisy, noisy, lights)
        error = yb.angular_error_deg(full["normal"][mask], normal[mask]).mean()
        self.assertGreater(error, 0.3)          # the noise is visible in the full solution
        self.assertGreater(angle.mean() / error, 1.5)
        self.assertLess(angle.mean() / error, 3.0)


class LightConvention(unittest.TestCase):
    def test_yale_azimuth_and_elevation_in_the_camera_frame(self):
        # Hand-computed: a positive azimuth lights the viewer's left (-X), elevation is up (+Y).
        np.testing.assert_allclose(yb.light_direction(0, 0), [0, 0, 1], atol=1e-12)
        np.testing.assert_allclose(yb.light_direction(90, 0), [-1, 0, 0], atol=1e-12)
        np.testing.assert_allclose(yb.light_direction(-90, 0), [1, 0, 0], atol=1e-12)
        np.testing.assert_allclose(yb.light_direction(0, 90), [0, 1, 0], atol=1e-12)
        s = math.sqrt(0.5)
        np.testing.assert_allclose(yb.light_direction(45, 0), [-s, 0, s], atol=1e-12)
        np.testing.assert_allclose(yb.light_direction(90, 45), [-s, s, 0], atol=1e-12)


class RelightYaw(unittest.TestCase):
    def test_turns_the_axis_light_to_the_strobe(self):
        """Ry(yaw) as facetool defines it (right-hand rule about +Y) applied to the camera axis
        gives the strobe's direction for every relighting target and a few more azimuths."""
        for a in (25, -25, 50, -50, 90):
            t = math.radians(yb.relight_yaw(a))
            turned = np.array([math.sin(t), 0.0, math.cos(t)])  # Ry(t) (0, 0, 1)
            np.testing.assert_allclose(turned, yb.light_direction(a, 0), atol=1e-12)


class FitPriorModels(unittest.TestCase):
    def test_reads_the_input_convention_from_the_weights_header(self):
        """A safetensors header written by hand (8-byte length, JSON): linear_rgb+fit_normal takes
        the fit prior and gets --face-model; linear_rgb and no model do not."""
        with tempfile.TemporaryDirectory() as tmp:
            def weights(name, input_convention):
                header = json.dumps({"__metadata__": {"format": "facetool-network", "input": input_convention}}).encode()
                path = os.path.join(tmp, name)
                with open(path, "wb") as f:
                    f.write(struct.pack("<Q", len(header)) + header)
                return path
            prior, plain = weights("prior.safetensors", "linear_rgb+fit_normal"), weights("plain.safetensors", "linear_rgb")
            self.assertTrue(yb.takes_fit_prior(prior))
            self.assertFalse(yb.takes_fit_prior(plain))
            self.assertFalse(yb.takes_fit_prior(None))
            args = type("Args", (), {"model": prior, "face_model": "/ict"})()
            self.assertEqual(yb.model_options(args), ["--model", prior, "--face-model", "/ict"])
            args.model = plain
            self.assertEqual(yb.model_options(args), ["--model", plain])


class Scorer(unittest.TestCase):
    def test_angles_against_hand_computed_values(self):
        up = np.array([0.0, 0.0, 1.0])
        preds = np.array([[0, 0, 1], [1, 0, 1], [0, 1, 0], [0, 0, -1],
                          [math.sin(math.radians(10)), 0, math.cos(math.radians(10))],
                          [0, 0, 3]], float)
        got = yb.angular_error_deg(preds, np.tile(up, (len(preds), 1)))
        np.testing.assert_allclose(got, [0, 45, 90, 180, 10, 0], atol=1e-6)

    def test_table_one_figures(self):
        # Photo 1: 10, 22, 28 degrees (mean 20); photo 2: 45 (mean 45); a photo not covered.
        r = yb.summarise([np.array([10.0, 22.0, 28.0]), np.array([45.0]), np.zeros(0)], 8)
        self.assertEqual(r["photos"], 2)
        self.assertAlmostEqual(r["mean"], 32.5)
        self.assertAlmostEqual(r["std"], 12.5)
        self.assertAlmostEqual(r["under20"], 25.0)   # 1 of 4 pixels
        self.assertAlmostEqual(r["under25"], 50.0)
        self.assertAlmostEqual(r["under30"], 75.0)
        self.assertAlmostEqual(r["coverage"], 0.5)   # 4 of 8 mask pixels
        self.assertAlmostEqual(r["pixel_mean"], 26.25)


class TemplateWarp(unittest.TestCase):
    def ellipsoid(self, alpha_deg, size=101, axes=(40.0, 25.0, 20.0)):
        """Orthographic normals of an ellipsoid turned by alpha about the camera's z axis (3D
        geometry, counter-clockwise seen from the camera), with the image positions of 4 points."""
        a, b, c = axes
        t = math.radians(alpha_deg)
        rot = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
        v, u = np.mgrid[0:size, 0:size].astype(np.float64)
        cx = (size - 1) / 2
        xy = np.stack([u - cx, -(v - cx)], -1)
        body = xy @ rot                                   # rot^T applied: back to the body frame
        q = 1 - (body[..., 0] / a) ** 2 - (body[..., 1] / b) ** 2
        inside = q > 0.05
        z = c * np.sqrt(np.maximum(q, 0))
        n_body = np.stack([body[..., 0] / a ** 2, body[..., 1] / b ** 2, z / c ** 2], -1)
        n_xy = n_body[..., :2] @ rot.T
        n = np.concatenate([n_xy, n_body[..., 2:]], -1)
        n /= np.linalg.norm(n, axis=-1, keepdims=True)
        pts_body = np.array([[20.0, 0], [-20, 5], [0, 15], [5, -12]])
        pts = pts_body @ rot.T
        pixels = np.stack([pts[:, 0] + cx, -pts[:, 1] + cx], -1)
        return np.where(inside[..., None], n, 0.0), inside, pixels

    def test_warped_normals_follow_the_faces_turn(self):
        target, t_valid, t_pts = self.ellipsoid(0.0)
        source, s_valid, s_pts = self.ellipsoid(25.0)
        m = yb.similarity(t_pts, s_pts)
        warped, w_valid = yb.warp_normals(source, s_valid, m, target.shape[:2])
        both = t_valid & w_valid
        both[1:-1, 1:-1] &= t_valid[:-2, 1:-1] & t_valid[2:, 1:-1]  # away from the rim
        err = yb.angular_error_deg(warped[both], target[both])
        self.assertGreater(both.sum(), 0.8 * t_valid.sum())
        self.assertLess(np.median(err), 0.5)
        # Without turning the normals by the map's rotation they would be off by degrees.
        t = math.radians(-25.0)
        unturned = np.stack([math.cos(t) * warped[..., 0] - math.sin(t) * warped[..., 1],
                             math.sin(t) * warped[..., 0] + math.cos(t) * warped[..., 1],
                             warped[..., 2]], -1)
        self.assertGreater(np.median(yb.angular_error_deg(unturned[both], target[both])), 3.0)


class PhotoLandmarks(unittest.TestCase):
    def test_reads_the_fits_and_infers_landmarks_and_nothing_else(self):
        pts = [[float(i), 2.0 * i + 0.5] for i in range(68)]
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "fitted"))
            with open(os.path.join(d, "fitted", "fit.json"), "w") as f:
                json.dump({"landmarks": pts, "pose": {}}, f)
            os.makedirs(os.path.join(d, "inferred"))
            with open(os.path.join(d, "inferred", "faces.json"), "w") as f:
                json.dump({"faces": [{"landmarks": pts[::-1]}, {"landmarks": pts}]}, f)
            os.makedirs(os.path.join(d, "no-face"))
            with open(os.path.join(d, "no-face", "faces.json"), "w") as f:
                json.dump({"faces": []}, f)
            np.testing.assert_array_equal(yb.photo_landmarks(d, "fitted"), np.array(pts))
            np.testing.assert_array_equal(yb.photo_landmarks(d, "inferred"), np.array(pts[::-1]))  # the first face
            self.assertIsNone(yb.photo_landmarks(d, "no-face"))
            self.assertIsNone(yb.photo_landmarks(d, "missing"))


class Pgm(unittest.TestCase):
    def test_reads_binary_pgm_with_a_comment(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "a.pgm")
            with open(path, "wb") as f:
                f.write(b"P5\n# a comment\n3 2\n255\n" + bytes([0, 10, 20, 30, 40, 255]))
            img = yb.read_pgm(path)
        np.testing.assert_array_equal(img, [[0, 10, 20], [30, 40, 255]])


if __name__ == "__main__":
    unittest.main(verbosity=2)
