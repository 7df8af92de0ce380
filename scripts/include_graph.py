#!/usr/bin/env python3
"""The product's include graph: cycles between files and between folders.

A node is a file without its extension, so that a header and its source count
as one (retina/retina.h and retina/retina.cpp are the node systems/retina).
An edge A -> B is an `#include "B"` in A that names a file of the product.
Tests, benchmarks, fuzz targets and examples are not the product.

    include_graph.py [--root DIR]           print the cycles; exit 1 if any
    include_graph.py --dot FILE             also write the file graph (Graphviz)
    include_graph.py --folders              print the folder graph's edges
    include_graph.py --public FILE          check that FILE's header list is the
                                            include closure of its roots
    include_graph.py --public FILE --write  rewrite FILE's list from its roots

Exit status 1 when two files (or two folders) include each other directly or
through others, or when an include of a product file is not written as the
installed package's consumers write it, "layerlab/<path>".
"""
import argparse
import os
import re
import sys

PRODUCT_FOLDERS = ["framework", "metrics", "lenses", "elements", "systems", "eye", "kernels", "retina", "targets", "calibration", "solvers",
                   "analysis", "app", "tools", "python/src", "include"]
EXTENSIONS = (".h", ".cpp", ".def", ".inc")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def product_files(root):
    for folder in PRODUCT_FOLDERS:
        base = os.path.join(root, folder)
        for parent, dirs, names in os.walk(base):
            dirs.sort()
            for name in sorted(names):
                if name.endswith(EXTENSIONS):
                    yield os.path.relpath(os.path.join(parent, name), root)
    yield from (name for name in ["layerlab.h"] if os.path.exists(os.path.join(root, name)))


def node_of(path):
    return os.path.splitext(path)[0]


def resolve(root, including, written):
    """The product file an include names, or None (a system or generated header)."""
    for base in (os.path.dirname(including), ""):
        candidate = os.path.normpath(os.path.join(base, written))
        if os.path.isfile(os.path.join(root, candidate)):
            return candidate
    if written.startswith("layerlab/"):
        return resolve(root, "", written[len("layerlab/"):])
    return None


def file_graph(root, unprefixed=None):
    """Edges between nodes; each include of a product file not written
    "layerlab/<path>" is appended to `unprefixed` as (file, written)."""
    files = list(product_files(root))
    known = set(files)
    edges = {}
    for path in files:
        with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
            text = f.read()
        source = node_of(path)
        edges.setdefault(source, set())
        for written in INCLUDE.findall(text):
            target = resolve(root, path, written)
            if target is None or target not in known:
                continue
            if unprefixed is not None and written != "layerlab/" + target:
                unprefixed.append((path, written))
            if node_of(target) != source:
                edges[source].add(node_of(target))
    return edges


def strongly_connected(edges):
    """Tarjan's algorithm, iterative; the components of more than one node."""
    index, low, on_stack, stack, components = {}, {}, set(), [], []
    counter = 0
    for start in sorted(edges):
        if start in index:
            continue
        work = [(start, iter(sorted(edges.get(start, ()))))]
        index[start] = low[start] = counter
        counter += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            advanced = False
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(edges.get(child, ())))))
                    advanced = True
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    components.append(sorted(component))
    return components


def folder_of(node):
    parts = node.split("/")
    return "/".join(parts[:2]) if parts[0] == "python" else (parts[0] if len(parts) > 1 else ".")


def folder_graph(edges):
    folders = {}
    for source, targets in edges.items():
        folders.setdefault(folder_of(source), set())
        for target in targets:
            if folder_of(target) != folder_of(source):
                folders[folder_of(source)].add(folder_of(target))
    return folders


def a_cycle(edges, component):
    """One cycle through the component's first node, as a path, for the message."""
    members = set(component)
    start = component[0]
    parent = {start: None}
    queue = [start]
    while queue:
        node = queue.pop(0)
        for child in sorted(edges.get(node, ())):
            if child == start:
                path = [node]
                while parent[path[-1]] is not None:
                    path.append(parent[path[-1]])
                return list(reversed(path)) + [start]
            if child in members and child not in parent:
                parent[child] = node
                queue.append(child)
    return component


def header_closure(root, roots):
    """The headers the roots include, directly or through other headers, roots included."""
    seen, queue = set(), list(roots)
    while queue:
        path = queue.pop()
        if path in seen:
            continue
        seen.add(path)
        with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
            for written in INCLUDE.findall(f.read()):
                target = resolve(root, path, written)
                if target is not None and not target.endswith(".cpp"):
                    queue.append(target)
    return sorted(seen)


def check_public(root, list_file, write):
    """The installed headers (cmake/public_headers.txt): `root X` lines name the
    public entry points, the other lines are their closure; 1 when they differ."""
    with open(list_file, encoding="utf-8") as f:
        lines = f.read().splitlines()
    header = [line for line in lines if line.startswith("#") or line.startswith("root ")]
    roots = [line.split(" ", 1)[1] for line in lines if line.startswith("root ")]
    listed = sorted(line for line in lines if line and not line.startswith(("#", "root ")))
    closure = header_closure(root, roots)
    if write:
        with open(list_file, "w", encoding="utf-8") as f:
            f.write("\n".join(header + closure) + "\n")
        print(f"{list_file}: {len(closure)} headers from {len(roots)} roots")
        return 0
    missing = sorted(set(closure) - set(listed))
    extra = sorted(set(listed) - set(closure))
    for path in missing:
        print(f"{list_file}: {path} is included by a public header but not listed (run with --write)")
    for path in extra:
        print(f"{list_file}: {path} is listed but no public header includes it (run with --write)")
    print(f"{len(closure)} public headers from {len(roots)} roots: {len(missing)} missing, {len(extra)} extra")
    return 1 if missing or extra else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    parser.add_argument("--dot")
    parser.add_argument("--folders", action="store_true")
    parser.add_argument("--public")
    parser.add_argument("--write", action="store_true")
    args = parser.parse_args()
    root = os.path.abspath(args.root)
    if args.public:
        return check_public(root, args.public, args.write)
    unprefixed = []
    edges = file_graph(root, unprefixed)
    folders = folder_graph(edges)
    if args.folders:
        for folder in sorted(folders):
            print(f"{folder} -> {', '.join(sorted(folders[folder])) or '(nothing)'}")
    if args.dot:
        with open(args.dot, "w") as f:
            f.write("digraph includes {\n  rankdir=BT;\n")
            for source in sorted(edges):
                for target in sorted(edges[source]):
                    f.write(f'  "{source}" -> "{target}";\n')
            f.write("}\n")
    file_cycles = strongly_connected(edges)
    folder_cycles = strongly_connected(folders)
    for component in file_cycles:
        print("file cycle: " + " -> ".join(a_cycle(edges, component)))
    for component in folder_cycles:
        print("folder cycle: " + " -> ".join(a_cycle(folders, component)))
    for path, written in unprefixed:
        print(f'{path}: #include "{written}" should read "layerlab/<path from the repository root>"')
    count = sum(len(t) for t in edges.values())
    print(f"{len(edges)} files (a header and its source as one), {count} includes between them, "
          f"{len(folders)} folders: {len(file_cycles)} file cycles, {len(folder_cycles)} folder cycles, "
          f"{len(unprefixed)} includes without the layerlab/ prefix")
    return 1 if file_cycles or folder_cycles or unprefixed else 0


if __name__ == "__main__":
    sys.exit(main())
