#!/usr/bin/env python3
"""The paper's network written independently in PyTorch: a speed reference and a format check.

  bench                      forward ms/image (batch 1 and 20) and a training step (batch 20,
                             Adam) on the CPU, to set beside `facetool bench network`
  bench-train                the full stage-1 step of `facetool bench train`: network, the SH
                             triple-product renderer and the paper's eight loss terms, Adam
                             (batch 20, 128x128, widths 32 64 128; data already in memory)
  export-random W.safetensors  random weights (including batch-norm statistics) in facetool's
                             format (docs/model-format.md), plus a 128x128 test image W.png
  compare W.safetensors RAW.safetensors [--mirror-average]
                             compares PyTorch's eval-mode outputs on W.png with the
                             `--raw-output` of `facetool infer --aligned --stretch W.png --model W.safetensors`
                             (--no-mirror-average; with --mirror-average, infer's default: the image's
                             outputs averaged with those of its mirror image seen back through the mirror)

Needs python3 with torch and numpy (Debian: python3-torch); facetool itself does not.
scripts/check-pytorch-parity.sh runs export-random, facetool infer and compare in one go.
"""
import argparse
import json
import struct
import sys
import time
import zlib

import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F

SLOPE = 0.2


class ConvBn(nn.Module):
    def __init__(self, cin, cout, k):
        super().__init__()
        self.conv = nn.Conv2d(cin, cout, k, padding=k // 2)
        self.bn = nn.BatchNorm2d(cout)

    def forward(self, x):
        return F.leaky_relu(self.bn(self.conv(x)), SLOPE)


class ResBlock(nn.Module):
    def __init__(self, c):
        super().__init__()
        self.bn1, self.conv1 = nn.BatchNorm2d(c), nn.Conv2d(c, c, 3, padding=1)
        self.bn2, self.conv2 = nn.BatchNorm2d(c), nn.Conv2d(c, c, 3, padding=1)

    def forward(self, x):
        h = self.conv1(F.leaky_relu(self.bn1(x), SLOPE))
        h = self.conv2(F.leaky_relu(self.bn2(h), SLOPE))
        return x + h


class Residual(nn.Module):
    def __init__(self, c):
        super().__init__()
        for i in range(5):
            setattr(self, f"block{i}", ResBlock(c))
        self.bn = nn.BatchNorm2d(c)

    def forward(self, x):
        for i in range(5):
            x = getattr(self, f"block{i}")(x)
        return F.leaky_relu(self.bn(x), SLOPE)


class Decoder(nn.Module):
    def __init__(self, c, out):
        super().__init__()
        self.layer1, self.layer2 = ConvBn(c, c, 3), ConvBn(c, c // 2, 3)
        self.out = nn.Conv2d(c // 2, out, 1)

    def forward(self, x):
        x = F.interpolate(x, scale_factor=2, mode="bilinear", align_corners=False)
        return self.out(self.layer2(self.layer1(x)))


class Encoder(nn.Module):
    def __init__(self, c):
        super().__init__()
        self.layer1, self.layer2 = ConvBn(3, c // 2, 7), ConvBn(c // 2, c, 3)
        self.down = nn.Conv2d(c, c, 3, stride=2, padding=1)

    def forward(self, x):
        return F.leaky_relu(self.down(self.layer2(self.layer1(x))), SLOPE)


class Light(nn.Module):
    def __init__(self, c):
        super().__init__()
        self.layer1 = ConvBn(3 * c, c, 1)
        self.fc = nn.Linear(c, 27)

    def forward(self, x):
        return self.fc(self.layer1(x).mean(dim=(2, 3)))


class PaperNetwork(nn.Module):
    def __init__(self, c=128):
        super().__init__()
        self.encoder = Encoder(c)
        self.albedo_residual, self.shape_residual = Residual(c), Residual(c)
        self.albedo_decoder, self.shape_decoder = Decoder(c, 3), Decoder(c, 12)
        self.light = Light(c)

    def forward(self, x):
        f = self.encoder(x)
        a, s = self.albedo_residual(f), self.shape_residual(f)
        albedo = torch.sigmoid(self.albedo_decoder(a))
        shape = self.shape_decoder(s)
        normal = F.normalize(shape[:, 0:3], dim=1)
        light = self.light(torch.cat([f, a, s], dim=1))
        return albedo, normal, shape[:, 3:12], light


def write_safetensors(path, tensors, metadata):
    header, offset, blobs = {"__metadata__": metadata}, 0, []
    for name, t in tensors.items():
        data = t.detach().contiguous().numpy().astype("<f4").tobytes()
        header[name] = {"dtype": "F32", "shape": list(t.shape),
                        "data_offsets": [offset, offset + len(data)]}
        offset += len(data)
        blobs.append(data)
    text = json.dumps(header).encode()
    text += b" " * (-len(text) % 8)
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(text)) + text + b"".join(blobs))


def read_safetensors(path):
    with open(path, "rb") as f:
        raw = f.read()
    (length,) = struct.unpack("<Q", raw[:8])
    header = json.loads(raw[8:8 + length])
    out = {}
    for name, info in header.items():
        if name == "__metadata__":
            continue
        begin, end = info["data_offsets"]
        out[name] = np.frombuffer(raw[8 + length + begin:8 + length + end], "<f4").reshape(info["shape"])
    return out


def write_png(path, rgb):
    """8-bit RGB PNG, written by hand so that no imaging library is needed."""
    h, w, _ = rgb.shape
    rows = b"".join(b"\x00" + rgb[y].astype(np.uint8).tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def test_image(size, seed):
    """A smooth random colour field as 8-bit sRGB values."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:size, 0:size] / size
    channels = [sum(rng.normal() * np.sin((i + 1) * np.pi * (x * rng.random() + y * rng.random()) + rng.random() * 6)
                    for i in range(4)) for _ in range(3)]
    rgb = np.stack(channels, axis=-1)
    rgb = (rgb - rgb.min()) / (rgb.max() - rgb.min())
    return np.round(rgb * 255.0)


def srgb_to_linear(values):
    v = values / 255.0
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def export_random(args):
    torch.manual_seed(args.seed)
    net = PaperNetwork(args.width)
    with torch.no_grad():
        for m in net.modules():
            if isinstance(m, nn.BatchNorm2d):  # non-trivial statistics so eval mode is tested
                m.weight.uniform_(0.5, 1.5)
                m.bias.uniform_(-0.2, 0.2)
                m.running_mean.uniform_(-0.5, 0.5)
                m.running_var.uniform_(0.5, 2.0)
    tensors = {k: v for k, v in net.state_dict().items() if not k.endswith("num_batches_tracked")}
    metadata = {"format": "facetool-network", "format_version": "1", "architecture": "paper_network",
                "width": str(args.width), "input_size": "128", "input": "linear_rgb"}
    write_safetensors(args.weights, tensors, metadata)
    write_png(args.weights.rsplit(".", 1)[0] + ".png", test_image(128, args.seed))
    print(f"wrote {args.weights} ({sum(t.numel() for t in tensors.values() if t.dtype == torch.float32):,} "
          f"values) and its test image")


def compare(args):
    weights = read_safetensors(args.weights)
    width = weights["encoder.down.weight"].shape[0]
    net = PaperNetwork(width)
    net.load_state_dict({k: torch.from_numpy(v.copy()) for k, v in weights.items()}, strict=False)
    net.eval()
    image = srgb_to_linear(test_image(128, args.seed)).astype(np.float32)
    x = torch.from_numpy(image.transpose(2, 0, 1).copy())[None]
    with torch.no_grad():
        expected = dict(zip(["albedo", "normal", "visibility", "light"], net(x)))
        if args.mirror_average:
            mirrored = dict(zip(["albedo", "normal", "visibility", "light"], net(torch.flip(x, dims=[3]))))
            # x -> -x: the normal's x and the SH functions odd in x (x, xy, xz: 3, 4, 7) change sign.
            normal_sign = torch.tensor([-1.0, 1.0, 1.0]).view(1, 3, 1, 1)
            sh_sign = torch.ones(9)
            sh_sign[[3, 4, 7]] = -1.0
            back = {"albedo": torch.flip(mirrored["albedo"], dims=[3]),
                    "normal": torch.flip(mirrored["normal"], dims=[3]) * normal_sign,
                    "visibility": torch.flip(mirrored["visibility"], dims=[3]) * sh_sign.view(1, 9, 1, 1),
                    "light": mirrored["light"] * sh_sign.repeat(3).view(1, 27)}
            expected = {k: (expected[k] + back[k]) / 2 for k in expected}
            expected["normal"] = F.normalize(expected["normal"], dim=1)
    raw = read_safetensors(args.raw)
    worst = 0.0
    for name, tensor in expected.items():
        ours = raw[name].reshape(tensor.shape)
        diff = np.abs(ours - tensor.numpy())
        scale = max(1e-6, float(np.abs(tensor.numpy()).max()))
        rel = float(diff.max()) / scale
        worst = max(worst, rel)
        print(f"{name:11s} shape {list(tensor.shape)}  max |facetool - pytorch| {diff.max():.3e}  "
              f"relative to max |value| {rel:.3e}")
    ok = worst <= args.tolerance
    print(f"{'PASS' if ok else 'FAIL'}: worst relative difference {worst:.3e} (tolerance {args.tolerance:g})")
    return 0 if ok else 1


def median_seconds(fn, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return sorted(times)[len(times) // 2]


def bench(args):
    torch.set_num_threads(args.threads)
    net = PaperNetwork(args.width)
    print(f"PyTorch {torch.__version__}, {torch.get_num_threads()} threads, width {args.width}, 128x128")
    net.eval()
    with torch.no_grad():
        for batch in (1, 20):
            x = torch.rand(batch, 3, 128, 128)
            net(x)
            t = median_seconds(lambda: net(x), args.repeats)
            print(f"forward (eval)      batch {batch:2d}  {1000 * t / batch:8.1f} ms/image")
    net.train()
    opt = torch.optim.Adam(net.parameters(), lr=1e-4)
    x = torch.rand(20, 3, 128, 128)

    def step():
        opt.zero_grad()
        albedo, normal, visibility, light = net(x)
        loss = albedo.square().mean() + normal.square().mean() + visibility.square().mean() + light.square().mean()
        loss.backward()
        opt.step()

    step()
    t = median_seconds(step, args.repeats)
    print(f"training step       batch 20  {t:8.2f} s  ({20 / t:.2f} images/s)")


SH_K = (0.28209479177387814347, 0.48860251190291992159, 1.09254843059207907054,
        0.31539156525252000603, 0.54627421529603953527)


def sh_basis(x, y, z):
    """The 9 real SH in facetool's order and sign (docs/conventions.md), stacked on a new last axis."""
    k0, k1, k2, k20, k22 = SH_K
    return torch.stack([torch.full_like(x, k0), k1 * y, k1 * z, k1 * x, k2 * x * y, k2 * y * z,
                        k20 * (3 * z * z - 1), k2 * x * z, k22 * (x * x - y * y)], -1)


def triple_product_table():
    """T_ijk = integral of Y_i Y_j Y_k over the sphere (Gauss-Legendre x uniform azimuth; exact)."""
    t, w = np.polynomial.legendre.leggauss(8)
    phi = np.arange(16) * (2 * np.pi / 16)
    tt, pp = np.meshgrid(t, phi, indexing="ij")
    st = np.sqrt(1 - tt * tt)
    y = sh_basis(torch.tensor(st * np.cos(pp)), torch.tensor(st * np.sin(pp)), torch.tensor(tt))
    weight = torch.tensor(np.repeat(w[:, None], 16, 1) * (2 * np.pi / 16))
    return torch.einsum("ab,abi,abj,abk->ijk", weight, y, y, y).float()


def light_gram(count=64000):
    """G_ij = mean over `count` Fibonacci directions of Y_i Y_j (the E_L directions)."""
    s = torch.arange(count, dtype=torch.float64)
    z = 1 - (2 * s + 1) / count
    phi = s * np.pi * (3 - np.sqrt(5))
    r = torch.sqrt(1 - z * z)
    y = sh_basis(r * torch.cos(phi), r * torch.sin(phi), z)
    return (y.T @ y / count).float()


def render(albedo, normal, visibility, light, table, mask):
    """albedo / pi * sum_ijk T_ijk L_i v_j c_k(n), c_k = A_l Y_k(n / |n|), inside the mask."""
    n = F.normalize(normal, dim=1)
    band = torch.tensor([np.pi] + [2 * np.pi / 3] * 3 + [np.pi / 4] * 5)
    c = sh_basis(n[:, 0], n[:, 1], n[:, 2]) * band  # [N,H,W,9]
    m = torch.einsum("ijk,nci->ncjk", table, light.view(-1, 3, 9))
    shading = torch.einsum("ncjk,njhw,nhwk->nchw", m, visibility, c) / np.pi
    return albedo * shading * mask


def masked_mse(x, y, mask):
    return ((x - y).square() * mask).sum() / (x.shape[1] * mask.sum())


def bench_train(args):
    torch.set_num_threads(args.threads)
    table, gram = triple_product_table(), light_gram()
    size, batch = 128, 20
    print(f"PyTorch {torch.__version__}, {torch.get_num_threads()} threads: full stage-1 step, "
          f"batch {batch}, {size}x{size}, 8 terms, Adam")
    g = torch.Generator().manual_seed(1)
    yy, xx = torch.meshgrid(torch.linspace(1, -1, size), torch.linspace(-1, 1, size), indexing="ij")
    mask = ((xx * xx + yy * yy) < 0.8).float().expand(batch, 1, size, size)
    image = torch.rand(batch, 3, size, size, generator=g)
    t_albedo = 0.3 + 0.4 * torch.rand(batch, 3, size, size, generator=g)
    t_normal = torch.stack([xx, yy, torch.sqrt(torch.clamp(1 - xx * xx - yy * yy, min=0))]).expand(batch, 3, size, size)
    t_vis = torch.zeros(batch, 9, size, size)
    t_vis[:, 0] = 3.5449077
    t_light = torch.rand(batch, 27, generator=g)
    for width in args.widths:
        net = PaperNetwork(width)
        net.train()
        opt = torch.optim.Adam(net.parameters(), lr=1e-4)

        def terms(albedo, normal, visibility, light):
            def recon(a, n, v, l):
                return masked_mse(render(a, n, v, l, table, mask), image, mask)
            d = (light - t_light).view(-1, 9)
            return (recon(albedo, t_normal, t_vis, t_light) + 0.2 * recon(t_albedo, normal, t_vis, t_light)
                    + 0.2 * recon(t_albedo, t_normal, visibility, t_light)
                    + 0.01 * recon(t_albedo, t_normal, t_vis, light)
                    + masked_mse(albedo, t_albedo, mask) + 0.2 * masked_mse(normal, t_normal, mask)
                    + 0.2 * masked_mse(visibility, t_vis, mask) + 0.01 * ((d @ gram) * d).sum(1).mean())

        def step():
            opt.zero_grad()
            terms(*net(image)).backward()
            opt.step()

        outputs = [o.detach() for o in net(image)]

        def losses_alone():
            leaves = [o.clone().requires_grad_(True) for o in outputs]
            terms(*leaves).backward()

        step()
        t = median_seconds(step, args.repeats)
        losses_alone()
        tl = median_seconds(losses_alone, args.repeats)
        print(f"width {width:3d}  step {1000 * t:8.1f} ms  {batch / t:6.2f} images/s  "
              f"losses+render {1000 * tl:7.1f} ms ({100 * tl / t:.0f}%)")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    b = sub.add_parser("bench")
    b.add_argument("--width", type=int, default=128)
    b.add_argument("--threads", type=int, default=2)
    b.add_argument("--repeats", type=int, default=5)
    t = sub.add_parser("bench-train")
    t.add_argument("--widths", type=int, nargs="+", default=[32, 64, 128])
    t.add_argument("--threads", type=int, default=2)
    t.add_argument("--repeats", type=int, default=3)
    e = sub.add_parser("export-random")
    e.add_argument("weights")
    e.add_argument("--width", type=int, default=32)
    e.add_argument("--seed", type=int, default=1)
    c = sub.add_parser("compare")
    c.add_argument("weights")
    c.add_argument("raw")
    c.add_argument("--seed", type=int, default=1)
    c.add_argument("--tolerance", type=float, default=1e-3)
    c.add_argument("--mirror-average", action="store_true", help="expect infer's mirror-averaged outputs")
    args = parser.parse_args()
    if args.command == "bench":
        return bench(args)
    if args.command == "bench-train":
        return bench_train(args)
    if args.command == "export-random":
        return export_random(args)
    return compare(args)


if __name__ == "__main__":
    sys.exit(main() or 0)
