#!/usr/bin/env python3
"""Fails if a facetool library includes a header of a library its CMake target does not declare.

Reads <build>/facetool_layers.txt (written by cmake/FacetoolLibrary.cmake: each library's name,
its folders taken from its sources, and the libraries named in its DEPENDS), so the check follows
the folders wherever they are. A library may include its own headers, the compute core's
(facetool_core, which every library links) and those of the libraries it declares directly;
nothing of the program (apps/), the plugins or the tests.
usage: check_library_layering.py LAYERS_FILE SOURCE_DIR  |  check_library_layering.py --self-test
"""
import os
import re
import sys


def main(layers_file, source_dir):
    libraries = {}  # name -> (folders, declared)
    for line in open(layers_file):
        if line.startswith("#") or not line.strip():
            continue
        name, folders, declared = line.rstrip("\n").split("|")
        libraries[name] = (folders.split(), set(declared.split()))
    owner = {folder: name for name, (folders, _) in libraries.items() for folder in folders}
    if "facetool_core" not in libraries or len(libraries) < 2:
        print(f"FAIL: {layers_file} lists no libraries above the core")
        return 1
    include = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
    failures, checked = [], 0
    for name, (folders, declared) in sorted(libraries.items()):
        allowed = {name, "facetool_core"} | declared
        for folder in folders:
            directory = os.path.join(source_dir, folder)
            for file in sorted(os.listdir(directory)):
                if not file.endswith((".h", ".cpp")):
                    continue
                path = os.path.join(directory, file)
                for number, text in enumerate(open(path, encoding="utf-8"), 1):
                    match = include.match(text)
                    if not match:
                        continue
                    header = match.group(1)
                    if "/" not in header:
                        continue  # a header beside the file (generated kernels and the like)
                    checked += 1
                    target = owner.get(os.path.dirname(header))
                    where = f"{folder}/{file}:{number}"
                    if target is None:
                        failures.append(f"{where} ({name}) includes {header}, which belongs to no library")
                    elif target not in allowed:
                        failures.append(f"{where} ({name}) includes {header} of {target}, which {name} does not "
                                        f"declare (DEPENDS of its facetool_add_library)")
    for failure in failures:
        print("FAIL:", failure)
    if failures:
        return 1
    print(f"library layering: ok ({len(libraries)} libraries, {checked} includes checked)")
    return 0


def self_test():
    """The check on a made-up tree: an undeclared include fails, a declared one passes."""
    import tempfile
    with tempfile.TemporaryDirectory() as root:
        for folder, text in [("core/util", ""), ("libs/a", '#include "libs/b/b.h"\n#include "core/util/u.h"\n'),
                             ("libs/b", '#include "core/util/u.h"\n')]:
            os.makedirs(os.path.join(root, folder))
            open(os.path.join(root, folder, os.path.basename(folder) + ".h"), "w").write(text)
        layers = os.path.join(root, "layers.txt")
        open(layers, "w").write("facetool_core|core/util|\nlib_a|libs/a|\nlib_b|libs/b|\n")
        undeclared = main(layers, root)
        open(layers, "w").write("facetool_core|core/util|\nlib_a|libs/a|lib_b\nlib_b|libs/b|\n")
        declared = main(layers, root)
        open(os.path.join(root, "libs/b/b.h"), "a").write('#include "apps/tool/x.h"\n')
        outside = main(layers, root)
    ok = undeclared == 1 and declared == 0 and outside == 1
    print("self-test:", "ok" if ok else f"FAIL (undeclared {undeclared}, declared {declared}, outside {outside})")
    return 0 if ok else 1


if __name__ == "__main__":
    if sys.argv[1:] == ["--self-test"]:
        sys.exit(self_test())
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
