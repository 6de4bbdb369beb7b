#!/usr/bin/env python3
"""Command-line tests of nomec's mesh outputs (run by ctest as backend/<case>).

  outputs  default output names, binary STL layout, OBJ + MTL next to the output, PLY,
           atomic replacement (a failed compile leaves the old file and no temp files),
           write errors, --time-report, pipeline flags and usage errors
  admesh   offset outputs (the corpus Klein bottle, the Klein bottle example, a Möbius
           band) written as binary STL is checked by Debian's `admesh`: no
           edges needed fixing, no facets were added, no holes were filled
  save     --emit nome round trip on every example and every corpus nome1/nome3 file that
           --check accepts (and with -D overrides): the saved file checks without errors and
           its --emit summary equals the original's
  progress the progress line: never on a piped stderr; on a terminal (a pty) it is written
           and erased in place, leaving nothing but the diagnostics
  non_finite  nothing infinite or NaN is written: `nan`, `inf` and overflowing numbers in
           every numeric flag are usage errors (exit 2), an overflowing literal or expression
           is an error (exit 1), and a mesh whose placed geometry overflows is refused by the
           last check before writing in every format (exit 1, no file, an existing output and
           standard output untouched); binary STL refuses coordinates past 32-bit floats
"""
import argparse
import json
import os
import pty
import select
import shutil
import re
import stat
import struct
import subprocess
import sys
import tempfile

ROOT = os.getcwd()
FAILURES = []


def check(cond, what):
    if not cond:
        FAILURES.append(what)
        print(f"FAIL: {what}")


def run(nomec, args, cwd=None, timeout=None):
    p = subprocess.run([nomec, "--color", "never"] + args, cwd=cwd, capture_output=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr.decode("utf-8", "replace")


def src(rel):
    return os.path.join(ROOT, rel)


def summary(nomec, args):
    code, out, err = run(nomec, ["--emit", "summary", "-o", "-"] + args)
    check(code == 0, f"summary {args} exits 0 (got {code}: {err})")
    return json.loads(out)["meshes"] if code == 0 else []


def case_outputs(nomec, _admesh, _corpus):
    with tempfile.TemporaryDirectory() as tmp:
        # Default output name: the input's basename with the format's extension, in the cwd.
        code, _, err = run(nomec, ["--emit", "stl", src("examples/funnel_cube.nome")], cwd=tmp)
        stl = os.path.join(tmp, "funnel_cube.stl")
        check(code == 0 and os.path.isfile(stl), f"default STL name (exit {code}: {err})")
        if os.path.isfile(stl):
            data = open(stl, "rb").read()
            (count,) = struct.unpack_from("<I", data, 80)
            check(count == 96, f"funnel cube STL has 96 triangles (48 quads), got {count}")
            check(len(data) == 84 + 50 * count, "binary STL size is 84 + 50 per triangle")
        # Binary STL on standard output.
        code, out, _ = run(nomec, ["--emit", "stl", "-o", "-", src("examples/funnel_cube.nome")])
        check(code == 0 and len(out) == 84 + 50 * 96, "binary STL on stdout")

        # OBJ to a file: colours go to an MTL next to it.
        obj = os.path.join(tmp, "sub", "coloured.obj")
        os.makedirs(os.path.dirname(obj))
        code, _, err = run(nomec, ["--emit", "obj", "-o", obj, src("tests/mesh/testdata/output_obj_colours.nome")])
        check(code == 0, f"OBJ with colours (exit {code}: {err})")
        mtl = os.path.join(tmp, "sub", "coloured.mtl")
        if code == 0:
            text = open(obj).read()
            check("mtllib coloured.mtl" in text, "OBJ names its MTL")
            check("usemtl cff0000" in text and "usemtl c0000ff" in text, "OBJ switches materials per colour")
            check(os.path.isfile(mtl) and "Kd 1 0 0" in open(mtl).read(), "MTL holds the red material")
        # PLY to a file.
        ply = os.path.join(tmp, "x.ply")
        code, _, _ = run(nomec, ["--emit", "ply", "-o", ply, src("tests/mesh/testdata/output_ply_colours.nome")])
        check(code == 0 and open(ply).read().startswith("ply\nformat ascii 1.0\n"), "PLY file")

        # Atomic replacement: a failed compile leaves the existing output alone.
        old = os.path.join(tmp, "keep.stl")
        with open(old, "w") as f:
            f.write("previous output")
        code, _, err = run(nomec, ["--emit", "stl", "-o", old, src("tests/mesh/testdata/fail_non_manifold_edge.nome")])
        check(code == 1 and "[NonManifoldGeometry]" in err, f"non-manifold input exits 1 (got {code})")
        check(open(old).read() == "previous output", "failed compile keeps the previous output")
        # Geometry diagnostics in JSON, with the instance path in the message.
        code, out, _ = run(nomec, ["--emit", "stl", "-o", old, "--diagnostics-format", "json",
                                   src("tests/mesh/testdata/fail_non_manifold_edge.nome")])
        diags = json.loads(out)[0]["diagnostics"] if code == 1 else []
        check(any(d["code"] == "NonManifoldGeometry" and "outer.inner" in d["message"] for d in diags),
              "geometry errors appear in JSON diagnostics")
        # A check error also stops before evaluation.
        bad = os.path.join(tmp, "bad.nome")
        with open(bad, "w") as f:
            f.write("instance i nosuchmesh endinstance\n")
        code, _, err = run(nomec, ["--emit", "stl", "-o", old, bad])
        check(code == 1 and "[UnknownName]" in err, "check errors exit 1")
        check(open(old).read() == "previous output", "check errors keep the previous output")
        # A successful compile replaces it.
        code, _, _ = run(nomec, ["--emit", "stl", "-o", old, src("examples/funnel_cube.nome")])
        check(code == 0 and os.path.getsize(old) == 84 + 50 * 96, "successful compile replaces the output")
        leftovers = [n for n in os.listdir(tmp) if ".tmp." in n]
        check(not leftovers, f"no temporary files left behind: {leftovers}")
        # An existing FIFO (like /dev/null) is written in place, not replaced by a file.
        fifo = os.path.join(tmp, "pipe.stl")
        os.mkfifo(fifo)
        proc = subprocess.Popen([nomec, "--emit", "stl", "-o", fifo, src("examples/funnel_cube.nome")],
                                stderr=subprocess.PIPE)
        with open(fifo, "rb") as f:
            data = f.read()
        proc.wait(timeout=60)
        check(proc.returncode == 0 and len(data) == 84 + 50 * 96, "STL written through a FIFO")
        check(stat.S_ISFIFO(os.stat(fifo).st_mode), "the FIFO is still a FIFO")
        # Write errors are reported, exit 1.
        code, _, err = run(nomec, ["--emit", "stl", "-o", os.path.join(tmp, "no", "such", "x.stl"),
                                   src("examples/funnel_cube.nome")])
        check(code == 1 and "cannot create" in err, f"unwritable output exits 1 ({code}: {err})")

    # --time-report: one line per stage on stderr.
    code, _, err = run(nomec, ["--emit", "summary", "-o", "-", "--time-report", "--merge", "--subdivide", "1",
                               "--offset", "0.05", src("tests/mesh/testdata/cube_six_faces.nome")])
    check(code == 0, "time report run exits 0")
    for stage in ("parse+check", "evaluate", "merge", "subdivide", "offset", "write", "total"):
        check(re.search(rf"^\s+{re.escape(stage)}\s+[0-9.]+$", err, re.M), f"--time-report shows {stage}")

    # Pipeline flags.
    cube = src("tests/mesh/testdata/cube_six_faces.nome")
    m = summary(nomec, [cube])
    check(len(m) == 1 and m[0]["components"] == 6 and not m[0]["closed"], "unmerged cube is six squares")
    m = summary(nomec, ["--merge", "--merge-tolerance", "1e-9", cube])
    check(m and m[0]["euler"] == 2 and m[0]["closed"], "--merge-tolerance 1e-9 still closes the cube")
    cc = summary(nomec, ["--subdivide", "2", cube])
    dr = summary(nomec, ["--subdivide", "2", "--rule", "derose", cube])
    check(cc and dr and cc[0]["faces"] == 96 and dr[0]["faces"] == 96, "--subdivide 2 gives 96 faces")
    check(cc and dr and cc[0]["position_hash"] != dr[0]["position_hash"], "--rule derose moves vertices")
    after = summary(nomec, ["--subdivide", "1", "--offset", "0.1", "--subdivide-after", "1", cube])
    check(after and after[0]["faces"] == 4 * 48 and after[0]["closed"] and after[0]["orientable"],
          "--subdivide-after rounds the closed slab")

    # Usage errors exit 2.
    code, _, _ = run(nomec, ["--merge", cube])
    check(code == 2, "--merge without a mesh --emit is a usage error")
    code, _, _ = run(nomec, ["--emit", "stl", "--subdivide", "13", cube])
    check(code == 2, "--subdivide 13 is a usage error")

    # An input that cannot be read exits 2 and says why (a folder was once read as an empty
    # scene and passed); standard input is read to its end. A FIFO or a device is refused
    # without waiting on it or reading it (issue 45), and so is a file past --max-file-size.
    with tempfile.TemporaryDirectory() as tmp:
        fifo = os.path.join(tmp, "pipe.nome")
        os.mkfifo(fifo)
        for args, reason in ((["--check", tmp], "it is a folder, not a regular file"),
                             (["--check", os.path.join(tmp, "missing.nome")], "no such file or directory"),
                             (["--emit", "stl", "-o", os.path.join(tmp, "x.stl"), tmp], "it is a folder, not a regular file"),
                             (["--check", fifo], "it is a named pipe (FIFO), not a regular file"),
                             (["--check", "/dev/zero"], "it is a character device, not a regular file"),
                             (["--check", "--max-file-size", "100", cube],
                              f"it is {os.path.getsize(cube) / 1024:.1f} KiB, more than the 100 bytes nomec reads "
                              "(`--max-file-size`)")):
            try:
                code, _, err = run(nomec, args, timeout=60)
            except subprocess.TimeoutExpired:
                code, err = None, "timed out"
            check(code == 2 and f"cannot read `{args[-1]}`: {reason}" in err,
                  f"{args} exits 2 and says `{reason}` (exit {code}: {err})")
        fmt = subprocess.run([nomec, "fmt", tmp], capture_output=True, text=True)
        check(fmt.returncode == 2 and f"nomec fmt: cannot read `{tmp}`: it is a folder, not a regular file" in fmt.stderr,
              f"fmt of a folder exits 2 and says why (exit {fmt.returncode}: {fmt.stderr})")
        with open(cube, "rb") as f:
            piped = subprocess.run([nomec, "--color", "never", "--emit", "summary", "-o", "-", "/dev/stdin"],
                                   stdin=f, capture_output=True)
        check(piped.returncode == 0 and json.loads(piped.stdout)["meshes"] == summary(nomec, [cube]),
              f"a scene read from a pipe is the scene (exit {piped.returncode}: {piped.stderr[-300:]})")


# The flags that make each example a closed solid; every file in examples/ must be listed.
EXAMPLE_OFFSET = {
    "funnel_cube.nome": ["--merge", "--subdivide", "1", "--offset", "0.05"],
    "funnel_cube_consolidated.nome": ["--merge", "--subdivide", "1", "--offset", "0.05"],
    "klein_bottle.nome": ["--merge", "--subdivide", "1", "--offset", "0.05"],
    "klein_bottle_zipped.nome": ["--merge", "--subdivide", "1", "--offset", "0.05"],
    "mobius_band.nome": ["--merge", "--subdivide", "2", "--offset", "0.08"],
    "perry_tetra_single_sided.nome": ["--merge", "--subdivide", "2", "--offset", "0.08"],
    "zero.nome": ["--merge", "--subdivide", "2", "--offset", "0.03"],
    "handle_cube.nome": ["--merge", "--subdivide", "1", "--offset", "0.05"],
    "handle_funnels.nome": ["--merge", "--subdivide", "1", "--offset", "0.05"],
    "sierpinski_tetrahedron.nome": ["--merge", "--subdivide", "1", "--offset", "0.02"],
    "menger_sponge.nome": ["--merge", "--subdivide", "1", "--offset", "0.01"],
    "rind_sphere.nome": ["--merge", "--subdivide", "1", "--offset", "0.01"],
    "mobius_handle.nome": ["--merge", "--subdivide", "2", "--offset", "0.05"],
}
# Examples whose surface is single-sided before the offset.
NON_ORIENTABLE = ("mobius_band.nome", "perry_tetra_single_sided.nome", "klein_bottle_zipped.nome", "zero.nome",
                  "mobius_handle.nome")


def case_admesh(nomec, admesh, corpus):
    examples = sorted(f for f in os.listdir(src("examples")) if f.endswith(".nome"))
    check(examples == sorted(EXAMPLE_OFFSET), f"every example has offset flags ({examples})")
    for name in NON_ORIENTABLE:
        flags = ["--merge"] if name == "klein_bottle_zipped.nome" else []
        meshes = summary(nomec, flags + [src("examples/" + name)])
        check(meshes and not any(m["orientable"] for m in meshes), f"{name} is non-orientable before offset")
    zero = summary(nomec, ["--merge", os.path.join(corpus, "nome1/zero/zerosave.anom")])
    check(zero and len(zero) == 1 and not zero[0]["orientable"] and zero[0]["border_loops"] == 2,
          "corpus Zero (Zero_6.sif + zerosave.anom) merged is one single-sided surface")
    for name, flags in EXAMPLE_OFFSET.items():
        meshes = summary(nomec, flags + [src("examples/" + name)])
        check(meshes and all(m["closed"] and m["orientable"] and m["border_loops"] == 0 for m in meshes),
              f"{name}: offset output is closed and orientable by our checker")
    inputs = [(os.path.join("examples", name), flags) for name, flags in EXAMPLE_OFFSET.items()] + [
        (os.path.join(corpus, "nome1/kleinbottle/savetemp1.anom"),
         ["--merge", "--subdivide", "1", "--offset", "0.05", "--subdivide-after", "1"]),
        # Flat mesh files given to nomec are scenes: a closed tetrahedron in, the same out.
        ("tests/check/inputs/flat/tetra.stl", []),
        ("tests/check/inputs/flat/tetra_ascii.stl", []),
        # The seed's "Zero" from the corpus in place: Zero_6.sif plus zerosave.anom.
        (os.path.join(corpus, "nome1/zero/zerosave.anom"), ["--merge", "--subdivide", "2", "--offset", "0.002"]),
        ("tests/mesh/testdata/mobius_band_offset.nome", ["--merge", "--subdivide", "1", "--offset", "0.05"]),
        # A Menger sponge through `subdivision` and `offset` blocks (no command-line steps).
        ("tests/mesh/testdata/block_menger_subdivision_offset.nome", []),
        # Closed sweeps straight to STL: faces must already point outwards (none reversed).
        ("tests/mesh/testdata/sweep_capped.nome", []),
        (os.path.join(corpus, "nome3/sweeps_circle.nom"), []),
    ]
    with tempfile.TemporaryDirectory() as tmp:
        for rel, flags in inputs:
            stl = os.path.join(tmp, os.path.basename(rel) + ".stl")
            code, _, err = run(nomec, ["--emit", "stl", "-o", stl] + flags + [src(rel)])
            check(code == 0, f"{rel}: nomec exits 0 ({err})")
            if code != 0:
                continue
            p = subprocess.run([admesh, stl], capture_output=True, text=True)
            out = p.stdout
            check(p.returncode == 0, f"{rel}: admesh exits 0")

            def stat(label):
                m = re.search(rf"{re.escape(label)}\s*:\s*(\d+)", out)
                return int(m.group(1)) if m else None

            check("No holes need to be filled" in out, f"{rel}: admesh fills no holes")
            check(stat("Edges fixed") == 0, f"{rel}: admesh fixes no edges ({stat('Edges fixed')})")
            check(stat("Facets added") == 0, f"{rel}: admesh adds no facets ({stat('Facets added')})")
            check(stat("Facets reversed") == 0, f"{rel}: admesh reverses no facets")
            check(stat("Backwards edges") == 0, f"{rel}: no backwards edges")
            check(stat("Degenerate facets") == 0, f"{rel}: no degenerate facets")
            check(stat("Total disconnected facets") == 0, f"{rel}: no disconnected facets")


def corpus_files(corpus):
    for folder in ("nome1", "nome3"):
        for dirpath, dirnames, filenames in os.walk(os.path.join(corpus, folder)):
            dirnames.sort()
            for name in sorted(filenames):
                yield os.path.join(dirpath, name)


def meshes_without_file(out):
    return json.loads(out)["meshes"]


def case_save(nomec, _admesh, corpus):
    examples = sorted(os.path.join("examples", f) for f in os.listdir(src("examples")) if f.endswith(".nome"))
    # (input, extra flags): every example and accepted corpus file as is, plus overrides.
    inputs = [(src(e), []) for e in examples] + [(f, []) for f in corpus_files(corpus)]
    inputs += [
        (src("examples/funnel_cube.nome"), ["-D", "fp.n=5", "-D", "fp.z=-1"]),
        (os.path.join(corpus, "nome1/kleinbottle/s1.anom"), ["-D", "tp2.h=0.5"]),
        (os.path.join(corpus, "nome3/bank_sphere.nom"), ["-D", "funnel_slider.num_sides=7"]),
    ]
    tried = 0
    with tempfile.TemporaryDirectory() as tmp:
        for path, flags in inputs:
            code, _, _ = run(nomec, ["--check"] + flags + [path])
            if code != 0:
                continue
            tried += 1
            ext = os.path.splitext(path)[1]
            # Saved work and flat mesh files are saved as NOME scenes.
            saved = os.path.join(tmp, f"saved{tried}{'.nome' if ext in ('.anom', '.amom', '.sif') else ext}")
            code, _, err = run(nomec, ["--emit", "nome", "-o", saved] + flags + [path])
            check(code == 0 and os.path.isfile(saved), f"{path} {flags}: --emit nome ({err})")
            if code != 0:
                continue
            code, _, err = run(nomec, ["--check", saved])
            check(code == 0, f"{path} {flags}: the saved file checks clean ({err})")
            code_a, out_a, _ = run(nomec, ["--emit", "summary", "-o", "-"] + flags + [path])
            code_b, out_b, err = run(nomec, ["--emit", "summary", "-o", "-", saved])
            check(code_a == code_b, f"{path} {flags}: saved file emits like the original ({err})")
            if code_a == 0 and code_b == 0:
                check(meshes_without_file(out_a) == meshes_without_file(out_b),
                      f"{path} {flags}: the saved file's summary equals the original's")
        # The override is really in the saved text (not only in a trailing block).
        saved = os.path.join(tmp, "fc.nome")
        run(nomec, ["--emit", "nome", "-o", saved, "-D", "fp.n=5", src("examples/funnel_cube.nome")])
        text = open(saved).read()
        check(re.search(r"^\s*set\s+n\s+5\s", text, re.M) is not None, "-D fp.n=5 rewrites the `set n` line")
        check("savedparameter" not in text, "a 2016 file without savedparameter blocks gets none: its banks hold the values")
        # Default name: <stem>.saved<ext> in the working directory.
        code, _, _ = run(nomec, ["--emit", "nome", os.path.join(corpus, "nome3/torusknot.nom")], cwd=tmp)
        check(code == 0 and os.path.isfile(os.path.join(tmp, "torusknot.saved.nom")), "default saved name")
        check("savedparameter" not in open(os.path.join(tmp, "torusknot.saved.nom")).read(),
              "NOME3 saves carry no 2016 savedparameter block")
    check(tried >= 40, f"round trip covered {tried} files")


def read_pty(fd, proc):
    out = b""
    while True:
        r, _, _ = select.select([fd], [], [], 0.2)
        if r:
            try:
                chunk = os.read(fd, 65536)
            except OSError:
                break
            if not chunk:
                break
            out += chunk
        elif proc.poll() is not None:
            break
    return out.decode("utf-8", "replace")


def case_progress(nomec, _admesh, _corpus):
    args = ["--emit", "summary", "-o", os.devnull, "--merge", "--subdivide", "1", "--offset", "0.05",
            src("examples/klein_bottle.nome")]
    # Piped stderr: diagnostics only, no progress text or terminal control sequences.
    code, _, err = run(nomec, args)
    check(code == 0, "klein bottle pipeline exits 0")
    check("\r" not in err and "\x1b" not in err and "…" not in err, "no progress text on a piped stderr")
    # A terminal: stages are announced on one line, overwritten in place and cleared.
    master, slave = pty.openpty()
    proc = subprocess.Popen([nomec, "--color", "never"] + args, stdin=subprocess.DEVNULL,
                            stdout=subprocess.DEVNULL, stderr=slave)
    os.close(slave)
    tty = read_pty(master, proc)
    proc.wait()
    os.close(master)
    check(proc.returncode == 0, "klein bottle pipeline on a terminal exits 0")
    for stage in ("evaluate", "merge", "subdivide", "offset"):
        check(f"{stage}…" in tty, f"progress names the {stage} stage on a terminal")
    check(tty.rstrip("\r\n").endswith("\r\x1b[K") or tty.endswith("\x1b[K"),
          "the progress line is erased at the end")
    # What remains visible once the line is erased: the same diagnostics as when piped.
    visible = re.sub(r"\r\x1b\[K[^\r\n]*(?=\r\x1b\[K)", "", tty).replace("\r\x1b[K", "").replace("\r\n", "\n")
    check(visible == err, "apart from the erased progress line, the terminal shows what the pipe shows")


def case_what_if(nomec, _admesh, _corpus):
    funnel = src("examples/funnel_cube.nome")
    code, out, err = run(nomec, ["--what-if", "fp.z=-0.5", funnel])
    check(code == 0, f"--what-if exits 0 (got {code}: {err})")
    j = json.loads(out) if code == 0 else {}
    check(j.get("parameter") == "fp.z" and j.get("old_value") == -0.8 and j.get("value") == -0.5,
          f"--what-if names the parameter and both values: {j.get('parameter')} {j.get('old_value')} {j.get('value')}")
    check(j.get("nodes_in_graph") == 24, f"24 nodes in the funnel cube's graph, got {j.get('nodes_in_graph')}")
    check(j.get("nodes_reevaluated") == 14, f"fp.z re-evaluates 14 nodes, got {j.get('nodes_reevaluated')}")
    check(j.get("generators_rerun") == 0, "fp.z re-runs no generator")
    check(j.get("instances_retransformed") == 6, "fp.z re-transforms the six instances")
    check(j.get("changed_outputs") == ["cf"], f"only `cf` changes, got {j.get('changed_outputs')}")
    check(j.get("full_build_ms", 0) > 0 and "update_ms" in j, "both times are reported")
    # The summary after the move equals a fresh build with -D.
    fresh = summary(nomec, ["-D", "fp.z=-0.5", funnel])
    check(j.get("summary") == fresh, "the what-if summary equals a fresh -D build's")
    # Pipeline flags are honoured: merge + subdivide + offset run per component.
    code, out, err = run(nomec, ["--what-if", "fp.n=5", "--merge", "--subdivide", "1", "--offset", "0.02", funnel])
    check(code == 0, f"--what-if with pipeline flags exits 0 (got {code}: {err})")
    j = json.loads(out) if code == 0 else {}
    check(j.get("generators_rerun") == 1 and j.get("kernel_ops_rerun", 0) >= 3,
          f"fp.n re-runs the funnel once and the kernel steps: {j.get('generators_rerun')} {j.get('kernel_ops_rerun')}")
    fresh = summary(nomec, ["-D", "fp.n=5", "--merge", "--subdivide", "1", "--offset", "0.02", funnel])
    check(j.get("summary") == fresh, "the pipeline what-if summary equals a fresh -D build's")
    # Refusals: unknown slider (exit 1, JSON error), malformed argument (usage, exit 2).
    code, out, err = run(nomec, ["--what-if", "fp.nope=1", funnel])
    check(code == 1 and "no slider `fp.nope`" in json.loads(out or "{}").get("error", ""),
          f"unknown slider is refused (exit {code})")
    code, _, err = run(nomec, ["--what-if", "fp.z", funnel])
    check(code == 2 and "bank.param=value" in err, f"malformed --what-if is a usage error (exit {code})")


def case_slide_import(nomec, _admesh, corpus):
    # atomflwr.slf's geometry is the mesh file `js_atomflwr.stl`, which CreateSTLObject reads
    # next to the scene; the corpus does not hold it. With a tetrahedron in its place (4
    # triangles) the scene draws it through the file's `subdivision` (Catmull-Clark, nomec's
    # default of 2 levels for the lost slideui package): 4 → 12 → 48 quads, closed, χ = 2.
    scene = os.path.join(corpus, "slide", "atomflwr.slf")
    stl = src("tests/check/inputs/flat/tetra_ascii.stl")
    with tempfile.TemporaryDirectory() as d:
        shutil.copy(scene, os.path.join(d, "atomflwr.slf"))
        code, _, err = run(nomec, ["--emit", "summary", "-o", "-", os.path.join(d, "atomflwr.slf")])
        check("`js_atomflwr.stl`, which is not next to the scene" in err and "GeometryFailed" in err,
              f"without its STL, atomflwr.slf says so and draws nothing (exit {code}): {err[-300:]}")
        shutil.copy(stl, os.path.join(d, "js_atomflwr.stl"))
        meshes = summary(nomec, [os.path.join(d, "atomflwr.slf")])
        check(len(meshes) == 1 and meshes[0].get("faces") == 48 and meshes[0].get("euler") == 2
              and meshes[0].get("closed"), f"with it, the subdivided tetrahedron: {meshes}")


TRIANGLE = """bank b
  set x 1 0 10 1
endbank
point p ({expr $b_x} 0 0) endpoint
point q (0 1 0) endpoint
point r (0 0 1) endpoint
mesh m
  face f (p q r) endface
endmesh
instance i m {xform}endinstance
"""


def no_temp_files(folder):
    return not [n for n in os.listdir(folder) if ".tmp." in n]


def case_non_finite(nomec, _admesh, _corpus):
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "tri.nome")
        with open(scene, "w") as f:
            f.write(TRIANGLE.replace("{xform}", ""))
        out = os.path.join(tmp, "out.stl")
        code, _, err = run(nomec, ["--emit", "stl", "-o", out, scene])
        check(code == 0 and os.path.isfile(out), f"the triangle builds ({code}: {err})")
        os.remove(out)
        # Every number of the command line is finite: CLI11 and strtod read `nan`, `inf` and
        # `1e999999` (as infinity) as numbers, and they reached the output files.
        for flags in (["-D", "b.x=nan"], ["-D", "b.x=inf"], ["-D", "b.x=-Infinity"], ["-D", "b.x=1e999999"],
                      ["--allow-out-of-range", "-D", "b.x=nan"], ["--allow-out-of-range", "-D", "b.x=1e400"],
                      ["--offset", "nan"], ["--offset", "inf"], ["--offset", "1e999"], ["--merge", "--merge-tolerance", "nan"],
                      ["--merge", "--merge-tolerance", "inf"], ["--time", "nan"], ["--frame", "-inf"]):
            code, stdout, err = run(nomec, ["--emit", "stl", "-o", out] + flags + [scene])
            check(code == 2 and "is not a finite number" in err, f"{flags} is a usage error (exit {code}: {err})")
            check(not os.path.exists(out), f"{flags} writes nothing")
        code, _, err = run(nomec, ["--what-if", "b.x=nan", scene])
        check(code == 2 and "`nan` is not a finite number" in err, f"--what-if b.x=nan is a usage error ({code}: {err})")
        code, _, err = run(nomec, ["--what-if", "b.x=1e999", scene])
        check(code == 2 and "`1e999` is not a finite number" in err, f"--what-if b.x=1e999 is a usage error ({code})")
        # A literal that overflows, in the scene: an error where it is written.
        big = os.path.join(tmp, "big.nome")
        with open(big, "w") as f:
            f.write(TRIANGLE.replace("{xform}", "translate (1e999999 0 0) "))
        code, _, err = run(nomec, ["--emit", "obj", "-o", out, big])
        check(code == 1 and "[NumberTooLarge]" in err and not os.path.exists(out),
              f"1e999999 in a scene is an error and writes nothing ({code}: {err})")
        # A slider value (a finite one) that makes an expression overflow: an error at the
        # operation.
        times = os.path.join(tmp, "times.nome")
        with open(times, "w") as f:
            f.write(TRIANGLE.replace("{xform}", "").replace("{expr $b_x}", "{expr $b_x * 1e300}"))
        code, _, err = run(nomec, ["--emit", "ply", "-o", out, times])
        check(code == 0 and os.path.isfile(out), f"1 * 1e300 builds ({code}: {err})")
        if os.path.exists(out):
            os.remove(out)
        code, _, err = run(nomec, ["--emit", "ply", "-o", out, "--allow-out-of-range", "-D", "b.x=1e10", times])
        check(code == 1 and "10000000000 * 1e+300 is too large" in err and not os.path.exists(out),
              f"-D b.x=1e10 overflows `$b_x * 1e300`: an error, nothing written ({code}: {err})")

        # Placed geometry that overflows: refused by the last check in every format. An
        # existing output stays as it was, and no temporary file is left.
        huge = os.path.join(tmp, "huge.nome")
        with open(huge, "w") as f:
            f.write(TRIANGLE.replace("{xform}", "scale (1e300 1e300 1e300) ").replace("set x 1 0 10 1", "set x 1e10 0 1e11 1"))
        for emit, extra in (("stl", []), ("stl", ["--stl-ascii"]), ("obj", []), ("ply", []), ("summary", [])):
            keep = os.path.join(tmp, f"keep.{emit}")
            with open(keep, "w") as f:
                f.write("previous output")
            code, stdout, err = run(nomec, ["--emit", emit, "-o", keep] + extra + [huge])
            check(code == 1 and "[NonFiniteCoordinate]" in err and "instance `i`" in err and "which is not a finite point" in err,
                  f"--emit {emit} {extra} refuses a vertex at infinity ({code}: {err})")
            check(open(keep).read() == "previous output", f"--emit {emit} {extra} keeps the previous output")
            check(no_temp_files(tmp), f"--emit {emit} {extra} leaves no temporary file")
            code, stdout, err = run(nomec, ["--emit", emit, "-o", "-"] + extra + [huge])
            check(code == 1 and stdout == b"", f"--emit {emit} {extra} -o - writes nothing to stdout ({code}, {len(stdout)} bytes)")

        # Binary STL holds 32-bit floats: 1e39 is refused there, and written by the text formats.
        far = os.path.join(tmp, "far.nome")
        with open(far, "w") as f:
            f.write(TRIANGLE.replace("{xform}", "").replace("set x 1 0 10 1", "set x 1e39 0 1e40 1"))
        code, stdout, err = run(nomec, ["--emit", "stl", "-o", "-", far])
        check(code == 1 and stdout == b"" and "binary STL's 32-bit numbers" in err,
              f"binary STL refuses 1e39 ({code}: {err})")
        code, stdout, err = run(nomec, ["--emit", "stl", "--stl-ascii", "-o", "-", far])
        text = stdout.decode()
        check(code == 0 and "1.000000e+39" in text and "inf" not in text and "nan" not in text,
              f"ASCII STL writes 1e39 ({code}: {err})")
        # Close to the float limit, binary STL writes finite floats only (the normal too).
        near = os.path.join(tmp, "near.nome")
        with open(near, "w") as f:
            f.write(TRIANGLE.replace("{xform}", "scale (1e38 1e38 1e38) ").replace("set x 1 0 10 1", "set x 3 0 10 1"))
        code, stdout, err = run(nomec, ["--emit", "stl", "-o", "-", near])
        check(code == 0 and len(stdout) == 84 + 50, f"binary STL of a triangle near the float limit ({code}: {err})")
        if code == 0 and len(stdout) == 134:
            floats = struct.unpack_from("<12f", stdout, 84)
            check(all(abs(x) < float("inf") and x == x for x in floats), f"binary STL floats are finite: {floats}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=["outputs", "admesh", "save", "progress", "what_if", "slide_import", "non_finite"])
    ap.add_argument("--nomec", required=True)
    ap.add_argument("--admesh", default="admesh")
    ap.add_argument("--corpus", default=os.path.join(ROOT, "..", "shared", "corpus"))
    a = ap.parse_args()
    cases = {"outputs": case_outputs, "admesh": case_admesh, "save": case_save, "progress": case_progress,
             "what_if": case_what_if, "slide_import": case_slide_import, "non_finite": case_non_finite}
    cases[a.case](a.nomec, a.admesh, a.corpus)
    if FAILURES:
        print(f"{len(FAILURES)} check(s) failed")
        return 1
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
