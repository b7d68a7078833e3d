#!/usr/bin/env python3
"""Same-hour speed anchors for `facetool bench network`: PyTorch, ONNX Runtime and OpenVINO.

The network is scripts/pytorch_reference.py's PaperNetwork, an independent PyTorch definition of
the paper's architecture (random weights and batch-norm statistics; speed does not depend on
them). PyTorch times it directly; it is exported to ONNX once per size and ONNX Runtime and
OpenVINO time that file. facetool's own `bench network` runs interleaved with them (A B A B ...),
so every figure comes from the same minutes; the median over rounds is printed with the load
average seen during the run and the ratios to each anchor.

  run [--facetool build/bin/facetool] [--venv VENV] [--rounds 3] [--sizes 32x64,128x128]
      the whole comparison (needs python3 with torch, e.g. Debian's python3-torch, and a venv
      with onnxruntime and openvino from pip: never a facetool dependency)
  torch --width W --size S      one PyTorch measurement (JSON on stdout)
  export --width W --size S F   writes the ONNX file F (torch)
  ort F / openvino F            one ONNX Runtime / OpenVINO measurement (JSON; run in the venv)

PyTorch runs with libjemalloc preloaded when it is installed (Debian: libjemalloc2): with glibc's
allocator its training step pays page faults on every step (../shared/docs/performance-notes.md).
PyTorch's OpenMP threads and ONNX Runtime's pool are told not to spin while they wait (the
machines these figures come from are shared; spinning threads fight the other work for cores).
facetool's pool checks for work for at most 50 microseconds before it sleeps on a condition
variable (FACETOOL_SPIN_US; set it to 0 in this script's environment to time facetool sleeping at
once, as the anchors do).
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
THREADS = 2
JEMALLOC = "/usr/lib/x86_64-linux-gnu/libjemalloc.so.2"


def median_ms(fn, repeats):
    """Medians of the wall-clock and of the process CPU milliseconds (all threads) of fn()."""
    wall, cpu = [], []
    for _ in range(repeats):
        start, cpu_start = time.perf_counter(), time.process_time()
        fn()
        wall.append(1000 * (time.perf_counter() - start))
        cpu.append(1000 * (time.process_time() - cpu_start))
    return statistics.median(wall), statistics.median(cpu)


def record(result, key, timing, per):
    """result[key] = wall ms / per, result["cpu_" + key] = CPU ms / per."""
    result[key] = timing[0] / per
    result["cpu_" + key] = timing[1] / per


def torch_bench(args):
    import torch
    sys.path.insert(0, HERE)
    from pytorch_reference import PaperNetwork
    torch.set_num_threads(THREADS)
    torch.manual_seed(1)
    net = PaperNetwork(args.width)
    result = {"version": torch.__version__}
    net.eval()
    with torch.no_grad():
        for batch in (1, 20):
            x = torch.rand(batch, 3, args.size, args.size)
            net(x)
            record(result, f"forward_b{batch}_ms", median_ms(lambda: net(x), args.repeats), batch)
    net.train()
    opt = torch.optim.Adam(net.parameters(), lr=1e-4)
    x = torch.rand(20, 3, args.size, args.size)

    def step():
        opt.zero_grad()
        albedo, normal, visibility, light = net(x)
        loss = albedo.mean() + normal.mean() + visibility.mean() + light.mean()
        loss.backward()
        opt.step()

    step()
    wall, cpu = median_ms(step, max(2, args.repeats // 2))
    result["train_b20_images_per_s"] = 20000.0 / wall
    result["cpu_train_b20_ms"] = cpu / 20
    print(json.dumps(result))


def export(args):
    import torch
    sys.path.insert(0, HERE)
    from pytorch_reference import PaperNetwork
    torch.manual_seed(1)
    net = PaperNetwork(args.width)
    for module in net.modules():  # batch-norm statistics that are not the identity
        if isinstance(module, torch.nn.BatchNorm2d):
            module.running_mean.uniform_(-0.2, 0.2)
            module.running_var.uniform_(0.5, 2.0)
    net.eval()
    x = torch.rand(1, 3, args.size, args.size)
    torch.onnx.export(net, x, args.file, input_names=["image"],
                      output_names=["albedo", "normal", "visibility", "light"],
                      dynamic_axes={"image": {0: "batch"}}, opset_version=13)


def ort_bench(args):
    import numpy as np
    import onnxruntime as ort
    options = ort.SessionOptions()
    options.intra_op_num_threads = THREADS
    options.inter_op_num_threads = 1
    options.add_session_config_entry("session.intra_op.allow_spinning", "0")  # as PyTorch's
    session = ort.InferenceSession(args.file, options, providers=["CPUExecutionProvider"])
    size = session.get_inputs()[0].shape[2]
    result = {"version": ort.__version__}
    for batch in (1, 20):
        x = np.random.rand(batch, 3, size, size).astype(np.float32)
        session.run(None, {"image": x})
        record(result, f"forward_b{batch}_ms",
               median_ms(lambda: session.run(None, {"image": x}), args.repeats), batch)
    print(json.dumps(result))


def openvino_bench(args):
    import numpy as np
    import openvino as ov
    core = ov.Core()
    model = core.read_model(args.file)
    result = {"version": ov.__version__}
    for batch in (1, 20):
        size = model.inputs[0].get_partial_shape()[2].get_length()
        model.reshape({"image": [batch, 3, size, size]})
        compiled = core.compile_model(model, "CPU", {"INFERENCE_NUM_THREADS": THREADS,
                                                     "PERFORMANCE_HINT": "LATENCY",
                                                     "INFERENCE_PRECISION_HINT": "f32"})
        request = compiled.create_infer_request()
        x = np.random.rand(batch, 3, size, size).astype(np.float32)
        request.infer({0: x})
        record(result, f"forward_b{batch}_ms", median_ms(lambda: request.infer({0: x}),
                                                         args.repeats), batch)
    print(json.dumps(result))


def facetool_bench(facetool, width, size, repeats):
    out = subprocess.run([facetool, "bench", "network", "--width", str(width), "--input-size",
                          str(size), "--batches", "1,20", "--train-batch", "20", "--repeats",
                          str(repeats)], check=True, capture_output=True, text=True,
                         env=dict(os.environ, FACETOOL_NUM_THREADS=str(THREADS))).stdout
    result = {}
    for line in out.splitlines():
        m = re.match(r"(forward \(eval\)|forward \(eval, plain ops\)|training step \S+)\s+(\d+)\s+"
                     r"([\d.]+)\s+([\d.]+)\s+[\d.]+\s+([\d.]+)", line)
        if not m:
            continue
        kind, batch, ms, per_s = m.group(1), int(m.group(2)), float(m.group(3)), float(m.group(4))
        cpu = float(m.group(5))
        if kind == "forward (eval)":
            result[f"forward_b{batch}_ms"], result[f"cpu_forward_b{batch}_ms"] = ms, cpu
        elif kind.startswith("forward"):
            result[f"plain_forward_b{batch}_ms"] = ms
            result[f"cpu_plain_forward_b{batch}_ms"] = cpu
        else:
            result["train_b20_images_per_s"], result["cpu_train_b20_ms"] = per_s, cpu
    return result


def json_of(command, env=None):
    out = subprocess.run(command, check=True, capture_output=True, text=True, env=env).stdout
    return json.loads(out.strip().splitlines()[-1])


def run(args):
    me = os.path.abspath(__file__)
    venv_python = os.path.join(args.venv, "bin", "python3")
    # OpenMP threads that sleep instead of spinning between parallel regions: on a machine
    # shared with other work, spinning made PyTorch's batch-1 forward 100x slower here.
    torch_env = dict(os.environ, OMP_NUM_THREADS=str(THREADS), OMP_WAIT_POLICY="PASSIVE")
    if os.path.exists(JEMALLOC):  # keeping freed memory, as docs/backends.md's PyTorch figures
        torch_env["LD_PRELOAD"] = JEMALLOC
        torch_env["MALLOC_CONF"] = "retain:true,dirty_decay_ms:-1,muzzy_decay_ms:-1"
    else:
        print(f"note: {JEMALLOC} missing (apt-get install libjemalloc2): PyTorch runs on glibc malloc")
    sizes = [tuple(int(v) for v in s.split("x")) for s in args.sizes.split(",")]
    tmp = tempfile.mkdtemp(prefix="facetool-anchors-")
    results = {}  # (width, size, engine) -> list of dicts
    loads = []
    for width, size in sizes:
        subprocess.run([args.torch_python, me, "export", "--width", str(width), "--size", str(size),
                        os.path.join(tmp, f"net{width}_{size}.onnx")], check=True, env=torch_env,
                       capture_output=True)
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    for r in range(args.rounds):
        for width, size in sizes:
            onnx_file = os.path.join(tmp, f"net{width}_{size}.onnx")
            repeats = args.repeats if width * size <= 64 * 64 else max(3, args.repeats // 3)
            runs = [
                ("facetool", lambda: facetool_bench(args.facetool, width, size, repeats)),
                ("pytorch", lambda: json_of([args.torch_python, me, "torch", "--width", str(width),
                                             "--size", str(size), "--repeats", str(repeats)],
                                            torch_env)),
                ("onnxruntime", lambda: json_of([venv_python, me, "ort", onnx_file,
                                                 "--repeats", str(repeats)])),
                ("openvino", lambda: json_of([venv_python, me, "openvino", onnx_file,
                                              "--repeats", str(repeats)])),
            ]
            for engine, fn in runs:
                loads.append(os.getloadavg()[0])
                value = fn()
                results.setdefault((width, size, engine), []).append(value)
                print(f"round {r + 1} width {width} {size}x{size} {engine}: {json.dumps(value)}",
                      flush=True)
    finished = time.strftime("%H:%M UTC", time.gmtime())
    print(f"\nmedians over {args.rounds} interleaved rounds, {started} to {finished}, "
          f"{THREADS} threads, 1-minute load average during the runs: median "
          f"{statistics.median(loads):.1f}, max {max(loads):.1f}")

    def med(width, size, engine, key):
        values = [v[key] for v in results.get((width, size, engine), []) if key in v]
        return statistics.median(values) if values else None

    versions = {engine: results[(sizes[0][0], sizes[0][1], engine)][0].get("version", "")
                for engine in ("pytorch", "onnxruntime", "openvino")}
    print("versions: " + ", ".join(f"{k} {v}" for k, v in versions.items()))
    header = (f"{'network':<34} {'facetool':>9} {'plain':>8} {'PyTorch':>8} {'ORT':>8} "
              f"{'OpenVINO':>9}   ratios facetool/anchor (time; <1 = facetool faster)")
    print(header)
    for width, size in sizes:
        for batch in (1, 20):
            key = f"forward_b{batch}_ms"
            f = med(width, size, "facetool", key)
            plain = med(width, size, "facetool", f"plain_{key}")
            pt, ox, ov = (med(width, size, e, key) for e in ("pytorch", "onnxruntime", "openvino"))
            ratios = "  ".join(f"{name} {f / a:.2f}" for name, a in
                               (("PyTorch", pt), ("ORT", ox), ("OpenVINO", ov)) if a and f)
            print(f"width {width:>3}, {size}x{size}, forward b{batch:<2} ms/img {f or 0:>9.2f} "
                  f"{plain or 0:>8.2f} {pt or 0:>8.2f} {ox or 0:>8.2f} {ov or 0:>9.2f}   {ratios}")
        f = med(width, size, "facetool", "train_b20_images_per_s")
        pt = med(width, size, "pytorch", "train_b20_images_per_s")
        ratio = f"facetool/PyTorch images/s {f / pt:.2f}" if f and pt else ""
        print(f"width {width:>3}, {size}x{size}, train b20 img/s  {f or 0:>9.2f} {'':>8} "
              f"{pt or 0:>8.2f} {'':>8} {'':>9}   {ratio}")
    print(f"\nprocess CPU time (all threads), ms per image: the work done, whatever the wait "
          f"for a core")
    print(header)
    for width, size in sizes:
        for batch in (1, 20):
            key = f"cpu_forward_b{batch}_ms"
            f = med(width, size, "facetool", key)
            plain = med(width, size, "facetool", f"cpu_plain_forward_b{batch}_ms")
            pt, ox, ov = (med(width, size, e, key) for e in ("pytorch", "onnxruntime", "openvino"))
            ratios = "  ".join(f"{name} {f / a:.2f}" for name, a in
                               (("PyTorch", pt), ("ORT", ox), ("OpenVINO", ov)) if a and f)
            print(f"width {width:>3}, {size}x{size}, forward b{batch:<2} ms/img {f or 0:>9.2f} "
                  f"{plain or 0:>8.2f} {pt or 0:>8.2f} {ox or 0:>8.2f} {ov or 0:>9.2f}   {ratios}")
        f = med(width, size, "facetool", "cpu_train_b20_ms")
        pt = med(width, size, "pytorch", "cpu_train_b20_ms")
        ratio = f"facetool/PyTorch CPU ms {f / pt:.2f}" if f and pt else ""
        print(f"width {width:>3}, {size}x{size}, train b20 ms/img  {f or 0:>9.2f} {'':>8} "
              f"{pt or 0:>8.2f} {'':>8} {'':>9}   {ratio}")
    json_path = os.path.join(tmp, "results.json")
    with open(json_path, "w") as out:
        json.dump({f"{w}x{s}/{e}": v for (w, s, e), v in results.items()}, out, indent=1)
    print(f"raw figures: {json_path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run")
    r.add_argument("--facetool", default="build/bin/facetool")
    r.add_argument("--torch-python", default=sys.executable,
                   help="a python3 with torch (Debian: python3-torch); default: this one")
    r.add_argument("--venv", default=os.environ.get("FACETOOL_ANCHOR_VENV", "/tmp/venv-anchors"))
    r.add_argument("--rounds", type=int, default=3)
    r.add_argument("--repeats", type=int, default=9)
    r.add_argument("--sizes", default="32x64,128x128", help="WIDTHxINPUT,...")
    for name in ("torch", "export"):
        p = sub.add_parser(name)
        p.add_argument("--width", type=int, required=True)
        p.add_argument("--size", type=int, required=True)
        p.add_argument("--repeats", type=int, default=9)
        if name == "export":
            p.add_argument("file")
    for name in ("ort", "openvino"):
        p = sub.add_parser(name)
        p.add_argument("file")
        p.add_argument("--repeats", type=int, default=9)
    args = parser.parse_args()
    return {"run": run, "torch": torch_bench, "export": export, "ort": ort_bench,
            "openvino": openvino_bench}[args.command](args)


if __name__ == "__main__":
    sys.exit(main() or 0)
