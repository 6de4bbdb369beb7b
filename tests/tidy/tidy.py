#!/usr/bin/env python3
"""Tidy checks over the repository, run by ctest (see CMakeLists.txt).

  kinds-covered  every kind in frontend/diagnostics/kinds.def appears as `[Kind]` in some
                 golden file under tests/ (the diagnostic-kind coverage test)
  emit-sites     every kind is emitted from at least one `emit(DiagKind::Kind` site in the
                 code; prints the kinds emitted from several sites
  readmes        every top-level folder that holds code, and every code folder of the library,
                 tools and editor client, has a README.md
  layers         every #include is an edge ARCHITECTURE.md's `layers` block allows (folders
                 and third-party headers such as ANTLR, nlohmann-json, <filesystem>)
  layers-selftest  the layers check reports exactly the forbidden includes planted in
                 tests/tidy/fixtures/layers/
  headers        every source file starts with a comment saying what it is for
                 (engineering.md §8)

Usage: tidy.py CHECK [--root REPO]
"""
import argparse
import os
import re
import sys

# Kinds listed in kinds.def that no code emits yet. Each is a known gap, not a skip: the
# `emit-sites` check fails when one of these starts being emitted (remove it here and add a
# golden test) and `kinds-covered` expects exactly these to be missing from the goldens.
KNOWN_UNEMITTED = set()

# Top-level code folders known to lack a README.md, asserted exactly (the check fails when
# one gains its README, so the entry is removed here).
KNOWN_MISSING_README = set()

CODE_EXTS = {".cpp", ".cc", ".h", ".hpp", ".g4", ".py", ".ts", ".js", ".sh", ".cmake"}
SKIP_DIRS = {".git", "node_modules", "__pycache__"}


def kinds(root):
    path = os.path.join(root, "frontend", "diagnostics", "kinds.def")
    with open(path, encoding="utf-8") as f:
        return re.findall(r"^NOMEC_DIAG\((\w+),", f.read(), re.M)


def is_build_dir(name):
    return name.startswith("build") or name.startswith("cmake-build")


def walk(top):
    for dirpath, dirnames, filenames in os.walk(top):
        dirnames[:] = sorted(d for d in dirnames if d not in SKIP_DIRS and not is_build_dir(d))
        for name in sorted(filenames):
            yield os.path.join(dirpath, name)


def check_kinds_covered(root):
    golden_exts = (".nome", ".nom", ".slf", ".anom")
    seen = set()
    for path in walk(os.path.join(root, "tests")):
        if not path.endswith(golden_exts):
            continue
        with open(path, encoding="utf-8", errors="replace") as f:
            for line in f:
                if line.startswith("# CHECK:"):
                    seen.update(re.findall(r"\[(\w+)\]\s*$", line))
    all_kinds = kinds(root)
    missing = [k for k in all_kinds if k not in seen]
    unexpected = [k for k in missing if k not in KNOWN_UNEMITTED]
    stale = [k for k in KNOWN_UNEMITTED if k in seen]
    ok = True
    if unexpected:
        ok = False
        print("diagnostic kinds that no golden file under tests/ shows (add a focused test to "
              "tests/check/testdata/):")
        for k in unexpected:
            print(f"  [{k}]")
    if stale:
        ok = False
        print("kinds listed in KNOWN_UNEMITTED now appear in goldens; remove them from tidy.py:")
        for k in stale:
            print(f"  [{k}]")
    print(f"{len(all_kinds) - len(missing)}/{len(all_kinds)} kinds covered by golden files; "
          f"known gaps: {', '.join(sorted(KNOWN_UNEMITTED)) or 'none'}")
    return ok


def check_emit_sites(root):
    counts = {k: [] for k in kinds(root)}
    pattern = re.compile(r"\bemit\(\s*DiagKind::(\w+)")
    for top in ("frontend", "ir", "backend", "tools", "lsp"):
        d = os.path.join(root, top)
        if not os.path.isdir(d):
            continue
        for path in walk(d):
            if not path.endswith((".cpp", ".cc", ".h", ".hpp")):
                continue
            with open(path, encoding="utf-8", errors="replace") as f:
                text = f.read()
            for m in pattern.finditer(text):
                line_start = text.rfind("\n", 0, m.start()) + 1
                if text[line_start:m.start()].lstrip().startswith("//"):
                    continue  # an example in a comment, not an emit site
                line = text.count("\n", 0, m.start()) + 1
                counts.setdefault(m.group(1), []).append(f"{os.path.relpath(path, root)}:{line}")
    ok = True
    declared = set(kinds(root))
    for k, sites in counts.items():
        if k not in declared:
            ok = False
            print(f"emit(DiagKind::{k}) at {', '.join(sites)}: not declared in kinds.def")
    for k in kinds(root):
        sites = counts[k]
        if not sites and k not in KNOWN_UNEMITTED:
            ok = False
            print(f"[{k}] is declared in kinds.def but never emitted")
        if sites and k in KNOWN_UNEMITTED:
            ok = False
            print(f"[{k}] is now emitted ({', '.join(sites)}); remove it from KNOWN_UNEMITTED "
                  "and add a golden test")
    multi = {k: s for k, s in counts.items() if len(s) > 1}
    # Relaxed rule: at least one site per kind. Kinds with several sites are listed so a
    # reader can see where one kind is produced.
    print(f"{len(multi)} kinds are emitted from more than one site:")
    for k, s in sorted(multi.items()):
        print(f"  {k}: {len(s)} sites ({', '.join(s)})")
    return ok


# Folders below these whose own files include code need a README.md too (the code folders
# of the library, the tools and the editor client; tests and build outputs are not).
NESTED_README_TOPS = ("base", "frontend", "ir", "backend", "kernel", "lsp", "tools", "grammar", "fuzz", "bench",
                      os.path.join("editors", "vscode", "src"))
SOURCE_EXTS = {".cpp", ".cc", ".h", ".hpp", ".g4", ".ts", ".def"}


def check_readmes(root):
    ok = True
    for name in sorted(os.listdir(root)):
        d = os.path.join(root, name)
        if not os.path.isdir(d) or name.startswith(".") or is_build_dir(name) or name in SKIP_DIRS:
            continue
        has_code = any(os.path.splitext(p)[1] in CODE_EXTS or os.path.basename(p) == "CMakeLists.txt"
                       for p in walk(d))
        has_readme = os.path.isfile(os.path.join(d, "README.md"))
        if has_code and not has_readme and name not in KNOWN_MISSING_README:
            ok = False
            print(f"{name}/ holds code but has no README.md")
        if has_readme and name in KNOWN_MISSING_README:
            ok = False
            print(f"{name}/ now has a README.md; remove it from KNOWN_MISSING_README in tidy.py")
        if has_code and not has_readme and name in KNOWN_MISSING_README:
            print(f"known gap: {name}/ holds code but has no README.md")
    for top in NESTED_README_TOPS:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, top)):
            dirnames[:] = [d for d in dirnames if d not in SKIP_DIRS and not is_build_dir(d) and d != "out"]
            if any(os.path.splitext(f)[1] in SOURCE_EXTS for f in filenames) and "README.md" not in filenames:
                ok = False
                print(f"{os.path.relpath(dirpath, root)}/ holds code but has no README.md saying what it owns")
    return ok


def layer_rules(root):
    """The `layers` block of ARCHITECTURE.md: {layer: allowed layers} and
    [(header prefix, exact, allowed layers)]."""
    with open(os.path.join(root, "ARCHITECTURE.md"), encoding="utf-8") as f:
        text = f.read()
    m = re.search(r"```layers\n(.*?)```", text, re.S)
    if not m:
        raise SystemExit("ARCHITECTURE.md has no ```layers block")
    layers, external = {}, []
    for line in m.group(1).splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        left, _, right = line.partition(":")
        allowed = set(right.split())
        if left.startswith("<"):
            for h in left.split():
                exact = h.endswith(">")
                external.append((h.strip("<>"), exact, allowed))
        else:
            layers[left.strip()] = allowed
    return layers, external


def layer_of(rel, layers):
    parts = rel.replace(os.sep, "/").split("/")
    for n in range(len(parts), 0, -1):
        name = "/".join(parts[:n])
        if name in layers:
            return name
    return None


INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*([<"])([^>"]+)[>"]', re.M)


def layer_violations(root, scan_root):
    """Forbidden includes of the C++ files under scan_root (paths relative to scan_root are
    read as paths in the tree), with the rules of root's ARCHITECTURE.md."""
    layers, external = layer_rules(root)
    tops = {name.split("/")[0] for name in layers}
    out = []
    for path in walk(scan_root):
        if not path.endswith((".cpp", ".cc", ".h", ".hpp")):
            continue
        rel = os.path.relpath(path, scan_root).replace(os.sep, "/")
        if scan_root == root and rel.startswith("tests/tidy/fixtures/"):
            continue
        me = layer_of(rel, layers)
        if me is None:
            if rel.split("/")[0] in tops or "/" in rel:
                out.append(f"{rel}: in no layer of ARCHITECTURE.md")
            continue
        allowed = layers[me]
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()
        for m in INCLUDE.finditer(text):
            kind, inc = m.group(1), m.group(2)
            line = text.count("\n", 0, m.start()) + 1
            target = layer_of(inc, layers) if kind == '"' and inc.split("/")[0] in tops else None
            if target is not None:
                if target != me and "*" not in allowed and target not in allowed:
                    out.append(f"{rel}:{line}: {me} may not include {inc} ({target})")
                continue
            for prefix, exact, who in external:
                if (inc == prefix) if exact else inc.startswith(prefix):
                    if me not in who and "*" not in allowed:
                        out.append(f"{rel}:{line}: {me} may not include <{inc}> (only {' '.join(sorted(who))})")
                    break
    return out


def check_layers(root):
    bad = layer_violations(root, root)
    for v in bad:
        print(v)
    layers, _ = layer_rules(root)
    print(f"{len(bad)} forbidden includes; {len(layers)} layers")
    return not bad


FIXTURE_EXPECTED = [
    "backend/eval/reads_files.cpp:4: backend may not include <filesystem> (only base bench tests tools)",
    "frontend/check/uses_backend.cpp:4: frontend/check may not include backend/generators/generators.h (backend/generators)",
    "kernel/uses_ir.h:4: kernel may not include ir/ir.h (ir)",
    "lsp/uses_tools.cpp:4: lsp may not include tools/what_if.h (tools)",
    "tools/uses_kernel.cpp:4: tools may not include kernel/mesh.h (kernel)",
]


def check_layers_selftest(root):
    got = sorted(layer_violations(root, os.path.join(root, "tests", "tidy", "fixtures", "layers")))
    if got != FIXTURE_EXPECTED:
        print("the layers check did not report the planted forbidden includes exactly:")
        print("  expected:\n    " + "\n    ".join(FIXTURE_EXPECTED))
        print("  got:\n    " + "\n    ".join(got))
        return False
    print(f"the layers check reports all {len(got)} planted forbidden includes")
    return True


HEADER_EXTS = (".cpp", ".cc", ".h", ".hpp", ".g4", ".def", ".py", ".sh", ".cmake")


def check_headers(root):
    ok = True
    for path in walk(root):
        rel = os.path.relpath(path, root)
        name = os.path.basename(path)
        if not (path.endswith(HEADER_EXTS) or name == "CMakeLists.txt"):
            continue
        if "testdata" in rel.split(os.sep) or rel.split(os.sep)[0] in SKIP_DIRS or is_build_dir(rel.split(os.sep)[0]):
            continue
        with open(path, encoding="utf-8", errors="replace") as f:
            lines = f.read().splitlines()
        i = 1 if lines and lines[0].startswith("#!") else 0
        first = lines[i].strip() if i < len(lines) else ""
        if not first.startswith(("//", "#", "/*", '"""')):
            ok = False
            print(f"{rel}: does not start with a comment saying what the file is for")
    return ok


CHECKS = {
    "kinds-covered": check_kinds_covered,
    "emit-sites": check_emit_sites,
    "readmes": check_readmes,
    "layers": check_layers,
    "layers-selftest": check_layers_selftest,
    "headers": check_headers,
}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("check", choices=sorted(CHECKS) + ["all"])
    parser.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    args = parser.parse_args()
    names = sorted(CHECKS) if args.check == "all" else [args.check]
    ok = True
    for n in names:
        ok = CHECKS[n](args.root) and ok
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
