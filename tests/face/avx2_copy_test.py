#!/usr/bin/env python3
"""The detector's AVX2 copy (libs/face/face_detector_engine_avx2.cpp) in its object file:
AVX instructions in its own and dlib's renamed code (the target pragma works), none in any code
the linker could share with the rest of the program (standard library and facetool inline
functions, kept for the baseline CPU: one copy of them serves the whole program, so an AVX one
would crash on a CPU without AVX2), and no fused multiply-adds (the portable copy's arithmetic).

    avx2_copy_test.py OBJECT_FILES...   (the facetool_face library's objects; ';'-separated too)
"""
import re
import shutil
import subprocess
import sys

# A function whose name holds the renamed dlib namespace or facetool::avx2 (as its own or in a
# template argument) exists in this object only.
OWN = ("facetool_dlib_avx2::", "facetool::avx2::")


def is_own(name):
    return any(tag in name for tag in OWN)


def main():
    objects = [p for arg in sys.argv[1:] for p in arg.split(";") if p.endswith("face_detector_engine_avx2.cpp.o")]
    if not objects:
        print("SKIP: no face_detector_engine_avx2.cpp object (not an x86-64 GCC or Clang build)")
        return 77
    if not (shutil.which("objdump") and shutil.which("nm") and shutil.which("c++filt")):
        print("SKIP: needs binutils (objdump, nm, c++filt)")
        return 77
    obj = objects[0]
    # Functions another object may define too: global and weak (template, inline) definitions.
    shared = set()
    for line in subprocess.run(["nm", "--defined-only", obj], capture_output=True, text=True, check=True).stdout.splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[1] in ("T", "W", "V", "u"):
            shared.add(parts[2])
    listing = subprocess.run(["objdump", "-d", "--no-show-raw-insn", obj], capture_output=True, text=True,
                             check=True).stdout
    avx, fma = {}, {}
    current = None
    for line in listing.splitlines():
        m = re.match(r"^[0-9a-f]+ <(.+)>:$", line)
        if m:
            current = m.group(1)
            continue
        m = re.match(r"^\s+[0-9a-f]+:\s+(\S+)", line)
        if current and m:
            mnemonic = m.group(1)
            if mnemonic.startswith("v") or "%ymm" in line or "%zmm" in line:  # VEX/EVEX encoded
                avx[current] = avx.get(current, 0) + 1
            if re.match(r"v?f(n)?m(add|sub)", mnemonic):
                fma[current] = fma.get(current, 0) + 1
    names = sorted(set(avx) | set(fma))
    demangled = dict(zip(names, subprocess.run(["c++filt"], input="\n".join(names), capture_output=True, text=True,
                                               check=True).stdout.splitlines())) if names else {}
    own = [f for f in avx if is_own(demangled[f])]
    leaked = [f for f in avx if f in shared and not is_own(demangled[f])]
    print(f"{obj}: {len(avx)} functions with AVX instructions, {len(own)} of them the copy's own "
          f"(dlib renamed, facetool::avx2); {len(leaked)} shared; {len(fma)} with fused multiply-adds")
    failures = 0
    if not any("fhog" in demangled[f] for f in own) or not any("spatially_filter" in demangled[f] for f in own):
        print("FAIL: dlib's HOG features and filters are not compiled for AVX2 in the copy")
        failures += 1
    for f in leaked:
        print(f"FAIL: shared function compiled with AVX: {demangled[f][:200]}")
        failures += 1
    for f in fma:
        print(f"FAIL: fused multiply-add in {demangled[f][:200]}")
        failures += 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
