#!/usr/bin/env python3
"""Checks the folder layering of include/unjam/ and src/ (docs/architecture.md, "Layers").

Usage: check_layers.py [SOURCE_DIR]   (default: the repository holding this script)

Every file under include/unjam/<folder>/ or src/<folder>/ belongs to <folder>. A file may
include, by `#include "unjam/<folder>/..."` (or <unjam/...>), headers of its own folder and
of folders in lower layers only: never a higher layer, nor another folder of its own layer.
A quoted include that does not start with unjam/ must name a file of the including file's
own folder, relative to it (no `../` into another folder). Exit 0 when every include obeys,
1 with one line per offending include (file:line, the include, why) otherwise.
"""

import os
import re
import sys

# The layer order, lowest first: the one place that defines it. A folder may include its
# own folder and every folder of a lower layer; folders of one layer are independent of
# each other. A new folder under include/unjam/ or src/ must be added here.
LAYERS = [
    ("scene", "lp", "parallel"),   # plain data of a scene; the LP builder loaded into CLP;
                                   # the worker threads of the library
    ("contacts",),                 # contact detection
    ("problem",),                  # assembly of the ContactProblem, Delassus form, LPs of a step
    ("solvers",),                  # backends, residual, pattern LP, rate path
    ("stepping",),                 # Simulation
    ("indeterminacy", "analysis"), # force networks of static packings; measurements, statistics
    ("protocols",),                # static solve, packings, relax, perturbations and their ensembles
    ("io",),                       # files
    ("cli",),                      # the command line (src/cli only)
]

RANK = {folder: rank for rank, layer in enumerate(LAYERS) for folder in layer}
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^">]+)[">]')
SOURCE_SUFFIXES = (".hpp", ".h", ".cpp", ".cc", ".ipp", ".inl")


def layer_name(folder):
    return "/".join(LAYERS[RANK[folder]])


def folder_roots(source_dir):
    """(root directory, label) pairs whose immediate subfolders are the project's folders."""
    return [(os.path.join(source_dir, "include", "unjam"), "include/unjam"),
            (os.path.join(source_dir, "src"), "src")]


def check_file(path, rel, folder, folder_dir, errors):
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = f.readlines()
    in_block_comment = False
    for number, line in enumerate(lines, start=1):
        if in_block_comment:
            if "*/" not in line:
                continue
            line = line.split("*/", 1)[1]
            in_block_comment = False
        if line.lstrip().startswith("/*") and "*/" not in line:
            in_block_comment = True
            continue
        m = INCLUDE.match(line)
        if not m:
            continue
        bracket, name = m.group(1), m.group(2)
        closing = '"' if bracket == '"' else ">"
        where = f"{rel}:{number}: #include {bracket}{name}{closing}"
        if name.startswith("unjam/"):
            parts = name.split("/")
            target = parts[1] if len(parts) > 2 else ""
            if target not in RANK:
                errors.append(f"{where}: unjam/{target} is no folder of the layer list "
                              f"(tests/architecture/check_layers.py, LAYERS)")
            elif target == folder:
                continue
            elif RANK[target] > RANK[folder]:
                errors.append(f"{where}: {folder}/ (layer {RANK[folder]}: {layer_name(folder)}) "
                              f"includes {target}/, a higher layer ({RANK[target]}: {layer_name(target)})")
            elif RANK[target] == RANK[folder]:
                errors.append(f"{where}: {folder}/ includes {target}/, a folder of its own layer "
                              f"({RANK[folder]}: {layer_name(folder)}), which must stay independent")
            continue
        if bracket == "<":
            continue  # system and third-party headers
        resolved = os.path.normpath(os.path.join(os.path.dirname(path), name))
        inside = os.path.commonpath([resolved, folder_dir]) == folder_dir
        if not inside:
            errors.append(f"{where}: relative path out of {folder}/ into another folder; "
                          f"include another folder's header as \"unjam/<folder>/...\"")
        elif not os.path.isfile(resolved):
            errors.append(f"{where}: not a file of {folder}/ relative to the including file; "
                          f"include another folder's header as \"unjam/<folder>/...\"")


def main(argv):
    source_dir = os.path.abspath(argv[1] if len(argv) > 1 else
                                 os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
    errors, checked = [], 0
    for root, label in folder_roots(source_dir):
        if not os.path.isdir(root):
            errors.append(f"{label}: missing (is {source_dir} the repository?)")
            continue
        for entry in sorted(os.listdir(root)):
            entry_path = os.path.join(root, entry)
            if not os.path.isdir(entry_path):
                if entry.endswith(SOURCE_SUFFIXES):
                    errors.append(f"{label}/{entry}: outside every folder; move it into one")
                continue
            if entry not in RANK:
                errors.append(f"{label}/{entry}/: a folder not in the layer list "
                              f"(tests/architecture/check_layers.py, LAYERS)")
                continue
            for dirpath, _, filenames in os.walk(entry_path):
                for filename in sorted(filenames):
                    if not filename.endswith(SOURCE_SUFFIXES):
                        continue
                    path = os.path.join(dirpath, filename)
                    rel = os.path.relpath(path, source_dir)
                    check_file(path, rel, entry, os.path.normpath(entry_path), errors)
                    checked += 1
    if errors:
        print(f"check_layers: {len(errors)} include(s) break the layering "
              f"(docs/architecture.md, \"Layers\"):")
        for e in errors:
            print("  " + e)
        return 1
    order = " -> ".join("{" + ", ".join(layer) + "}" if len(layer) > 1 else layer[0] for layer in LAYERS)
    print(f"check_layers: {checked} files obey the layer order {order}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
