#!/usr/bin/env python3
"""Command-line tests of the user's data (issue 45), run by ctest as save/<case>.

  output_is_input  an output that is an input is refused, nothing written: `-o` naming the
                   scene (also as ./x, dir/../x, a symlink, a hard link), the default output
                   name of a mesh given as the scene (`--emit obj mesh.obj`), a mesh the
                   scene includes, a Tcl file it sources, an OBJ's MTL
  save             `--emit nome`: SLIDE's `CreateScale` values rewritten in place (BellShape.slf
                   once lost its sliders: 17 errors), a NOME 2016 file's one savedparameter block
                   updated at every save, no float noise, one header line, a save that would
                   lose a slider's value refused
  fmt              `nomec fmt -i`: through a symlink (the link stays), hard-linked and read-only
                   files refused and left alone, an edit saved while the file is formatted kept
  signals          SIGINT or SIGTERM while an output is written leaves no temporary file
"""
import argparse
import ctypes
import os
import re
import select
import shutil
import signal
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


def run(nomec, args, cwd=None):
    p = subprocess.run([nomec, "--color", "never"] + args, cwd=cwd, capture_output=True)
    return p.returncode, p.stdout, p.stderr.decode("utf-8", "replace")


def src(rel):
    return os.path.join(ROOT, rel)


def read(path):
    with open(path, "rb") as f:
        return f.read()


def write(path, text):
    with open(path, "w", newline="") as f:
        f.write(text)


def temps(folder):
    return [n for n in os.listdir(folder) if ".tmp." in n]


CUBE = read(src("tests/mesh/testdata/cube_six_faces.nome")).decode()


def case_output_is_input(nomec, _corpus):
    with tempfile.TemporaryDirectory() as d:
        scene = os.path.join(d, "scene.nome")
        write(scene, CUBE)
        os.makedirs(os.path.join(d, "sub"))
        os.symlink("scene.nome", os.path.join(d, "link.nome"))
        os.link(scene, os.path.join(d, "hard.nome"))
        for out in ("scene.nome", "./scene.nome", "sub/../scene.nome", scene, "link.nome", "hard.nome"):
            for emit in ("stl", "obj", "ply", "summary", "nome"):
                code, _, err = run(nomec, ["--emit", emit, "-o", out, "scene.nome"], cwd=d)
                check(code == 1 and "refusing to overwrite the input `scene.nome`" in err and "nothing written" in err,
                      f"--emit {emit} -o {out} (the input) is refused: exit {code}: {err}")
                check(read(scene) == CUBE.encode(), f"--emit {emit} -o {out}: the scene is intact")
        check(os.path.islink(os.path.join(d, "link.nome")), "the symlink is still a symlink")
        check(not temps(d), f"no temporary files: {temps(d)}")
        # A mesh given as the scene: its default output name is itself.
        for mesh, emit in (("quad.obj", "obj"), ("tetra.stl", "stl")):
            shutil.copy(src("tests/check/inputs/flat/" + mesh), os.path.join(d, mesh))
            before = read(os.path.join(d, mesh))
            code, _, err = run(nomec, ["--emit", emit, mesh], cwd=d)
            check(code == 1 and f"refusing to overwrite the input `{mesh}`" in err,
                  f"--emit {emit} {mesh} (default output = the input) is refused: exit {code}: {err}")
            check(read(os.path.join(d, mesh)) == before, f"{mesh} is intact")
        # A mesh the scene includes, an OBJ's MTL that is an input, a Tcl file a SLIDE scene sources.
        write(os.path.join(d, "uses.nome"), 'include "quad.obj"\ninstance q quad endinstance\n')
        before = read(os.path.join(d, "quad.obj"))
        code, _, err = run(nomec, ["--emit", "obj", "-o", "quad.obj", "uses.nome"], cwd=d)
        check(code == 1 and "refusing to overwrite the input `quad.obj`" in err,
              f"an included mesh as the output is refused: exit {code}: {err}")
        check(read(os.path.join(d, "quad.obj")) == before, "the included mesh is intact")
        write(os.path.join(d, "helper.tcl"), "set keep 1\n")
        write(os.path.join(d, "s.slf"), "tclinit {\n  source helper.tcl\n}\npoint p (0 0 0) endpoint\n"
                                        "point q (1 0 0) endpoint\npoint r (0 1 0) endpoint\nface f (p q r) endface\n"
                                        "object o (f) endobject\n")
        for emit in ("stl", "nome"):
            code, _, err = run(nomec, ["--emit", emit, "-o", "helper.tcl", "s.slf"], cwd=d)
            check(code == 1 and "refusing to overwrite the input `" in err and "helper.tcl" in err,
                  f"--emit {emit} over a sourced Tcl file is refused: exit {code}: {err}")
            check(read(os.path.join(d, "helper.tcl")) == b"set keep 1\n", "the sourced Tcl file is intact")
        # An OBJ's MTL (written beside it) that would overwrite an input: here a Tcl file.
        shutil.copy(os.path.join(d, "helper.tcl"), os.path.join(d, "paint.mtl"))
        write(os.path.join(d, "p.slf"), read(os.path.join(d, "s.slf")).decode().replace("helper.tcl", "paint.mtl"))
        code, _, err = run(nomec, ["--emit", "obj", "-o", "paint.obj", "p.slf"], cwd=d)
        check(code == 1 and "refusing to overwrite the input `" in err and "paint.mtl" in err,
              f"an OBJ whose MTL is an input is refused: exit {code}: {err}")
        check(not os.path.exists(os.path.join(d, "paint.obj")) and read(os.path.join(d, "paint.mtl")) == b"set keep 1\n",
              "nothing written, the input intact")
        # Other outputs are written as before.
        code, _, err = run(nomec, ["--emit", "stl", "-o", "out.stl", "scene.nome"], cwd=d)
        check(code == 0 and os.path.getsize(os.path.join(d, "out.stl")) > 84, f"a new output is written: {err}")
        code, out, _ = run(nomec, ["--emit", "stl", "-o", "-", "scene.nome"], cwd=d)
        check(code == 0 and len(out) > 84, "standard output is never an input")
        check(not temps(d), f"no temporary files: {temps(d)}")


def case_save(nomec, corpus):
    slide = os.path.join(corpus, "slide")
    with tempfile.TemporaryDirectory() as d:
        # BellShape.slf: each `set q0x [CreateScale … 0.9 0 2 0.1 …]` keeps its call; the
        # moved value is its default argument.
        bell = os.path.join(slide, "BellShape.slf")
        original = read(bell).decode()
        saved = os.path.join(d, "BellShape.slf")
        code, _, err = run(nomec, ["--emit", "nome", "-o", saved, "-D", "swp.q0x=1", "-D", "swp.q3y=-4.1", bell])
        check(code == 0, f"BellShape.slf saves: exit {code}: {err}")
        text = read(saved).decode() if os.path.exists(saved) else ""
        check(text.count("[CreateScale ") == original.count("[CreateScale "), "every CreateScale call is kept")
        check(re.search(r'set q0x \[CreateScale \$name \$root q0x "q0x" +1 +0 +2 +0\.1 +1 horizontal\]', text),
              "q0x's default argument is the saved value")
        check(re.search(r'set q3y \[CreateScale \$name \$root q3y "q3y" +-4\.1 +-5 +0 +0\.1', text),
              "q3y's default argument is the saved value")
        check(text.split("\n", 1)[1] == original.replace('"q0x"                              0.9',
                                                         '"q0x"                              1', 1)
              .replace('"q3y"                             -4.0', '"q3y"                             -4.1', 1),
              "nothing else changed")
        # It checks clean (with nomec's versions of the Tcl helpers, not beside it here) and
        # reads back the saved values.
        code, out, err = run(nomec, ["--emit", "ir", saved])
        ir = out.decode()
        check(code == 0 and "error" not in err, f"the saved BellShape checks clean: exit {code}: {err[-400:]}")
        check("param `swp.q0x` 1 in" in ir and "param `swp.q3y` -4.1 in" in ir, "it reads back the saved values")

        # NOME 2016 saved work: its one savedparameter block is updated at every save.
        st = os.path.join(corpus, "nome1", "funnelCube", "st.anom")
        first, second = os.path.join(d, "s1.nome"), os.path.join(d, "s2.nome")
        code, _, err = run(nomec, ["--emit", "nome", "-o", first, "-D", "fp.n=6", st])
        check(code == 0, f"st.anom saves: {err}")
        code, _, err = run(nomec, ["--emit", "nome", "-o", second, "-D", "fp.n=7", "-D", "fp.ro=0.5", first])
        check(code == 0, f"the saved file saves again: {err}")
        for path, n in ((first, 6), (second, 7)):
            text = read(path).decode() if os.path.exists(path) else ""
            check(len(re.findall(r"^savedparameter$", text, re.M)) == 1, f"{path}: one savedparameter block")
            check(re.search(rf"^    fp_n {n}$", text, re.M), f"{path}: the block's fp_n is {n}")
            check(text.count("# Saved by nomec") == 1, f"{path}: one header line")
        text = read(second).decode() if os.path.exists(second) else ""
        check(re.search(r"^    fp_ro 0.5$", text, re.M), "fp.ro is changed in the block that sets it")

        # No float noise: 0.1 + 0.2 on a slider of step 0.1 is written 0.3.
        out = os.path.join(d, "fc.nome")
        code, _, err = run(nomec, ["--emit", "nome", "-o", out, "-D", "fp.ro=0.30000000000000004",
                                   src("examples/funnel_cube.nome")])
        text = read(out).decode() if code == 0 else ""
        check(re.search(r"^    set     ro       0\.3     0\.1", text, re.M) and "0000000" not in text,
              f"the value is written 0.3: {err}")

        # A save that cannot carry a moved slider is refused, nothing written: the slider's
        # value is set by a procedure of another file and the scene never reads it.
        scene = os.path.join(d, "off.slf")
        write(scene, "tclinit {\n  package require slideui\n  CreateSLIDEOffsetObject oOff\n"
                     "  CreateSLIDEOffsetUI .ui oOff\n}\npoint p (0 0 0) endpoint\n")
        out = os.path.join(d, "off.saved.slf")
        code, _, err = run(nomec, ["--emit", "nome", "-o", out, "-D", "oOff.height=0.5", scene])
        check(code == 1 and "slider `oOff.height` = 0.5 cannot be saved" in err and not os.path.exists(out),
              f"an unsaveable slider is refused: exit {code}: {err}")
        # GenusL_SymmDLh.slf sets each slider's variable after its `scale` (Tk's scale follows
        # its variable): the moved value is saved into that `set` and read back.
        genus = os.path.join(slide, "GenusL_SymmDLh.slf")
        out = os.path.join(d, "genus.slf")
        code, _, err = run(nomec, ["--emit", "nome", "-o", out, "-D", "x0.x0=0.5", genus])
        check(code == 0 and b"set x0 0.5" in read(out), f"GenusL's x0 is saved where the file sets it: exit {code}: {err}")
        code, out_text, err = run(nomec, ["--check", "-v", out])
        check(code == 0, f"the saved GenusL checks clean: exit {code}: {err}")
        # Unmoved, it saves as written.
        code, _, err = run(nomec, ["--emit", "nome", "-o", out, genus])
        check(code == 0 and read(out).decode().split("\n", 1)[1] == read(genus).decode(),
              f"an unmoved save is the file as written: {err}")


LIBC = ctypes.CDLL(None, use_errno=True)
IN_CLOSE_NOWRITE, IN_CREATE = 0x10, 0x100


def inotify(path, mask):
    fd = LIBC.inotify_init()
    check(fd >= 0 and LIBC.inotify_add_watch(fd, path.encode(), mask) >= 0, f"inotify on {path}")
    return fd


def events(fd, proc):
    """The names of inotify events on `fd` until `proc` ends (None then): no clock involved."""
    pidfd = os.pidfd_open(proc.pid)
    try:
        while True:
            ready, _, _ = select.select([fd, pidfd], [], [])
            if fd not in ready:
                return
            data = os.read(fd, 65536)
            at = 0
            while at < len(data):
                _, _, _, length = struct.unpack_from("iIII", data, at)
                name = data[at + 16:at + 16 + length].rstrip(b"\0").decode()
                at += 16 + length
                yield name
    finally:
        os.close(pidfd)


def case_fmt(nomec, _corpus):
    messy = "group g\ninstance i m   endinstance\nendgroup\n"
    clean = "group g\n    instance i m endinstance\nendgroup\n"
    with tempfile.TemporaryDirectory() as d:
        os.makedirs(os.path.join(d, "real"))
        target = os.path.join(d, "real", "s.nome")
        write(target, messy)
        link = os.path.join(d, "link.nome")
        os.symlink("real/s.nome", link)
        p = subprocess.run([nomec, "fmt", "-i", link], capture_output=True, text=True)
        check(p.returncode == 0, f"fmt -i through a symlink: {p.stderr}")
        check(os.path.islink(link) and os.readlink(link) == "real/s.nome", "the symlink stays a symlink")
        check(read(target).decode() == clean, "its target is formatted")
        check(not temps(d) and not temps(os.path.join(d, "real")), "no temporary files")

        a, b = os.path.join(d, "a.nome"), os.path.join(d, "b.nome")
        write(a, messy)
        os.link(a, b)
        ro = os.path.join(d, "ro.nome")
        write(ro, messy)
        os.chmod(ro, 0o444)
        other = os.path.join(d, "other.nome")
        write(other, messy)
        p = subprocess.run([nomec, "fmt", "-i", a, ro, other], capture_output=True, text=True)
        check(p.returncode == 2, f"fmt -i with refused files exits 2: {p.returncode}")
        check(f"`{a}` has 2 hard links" in p.stderr and "not rewritten" in p.stderr, f"the hard link is named: {p.stderr}")
        check(f"`{ro}` is read-only" in p.stderr, f"the read-only file is named: {p.stderr}")
        check(read(a).decode() == messy and os.stat(a).st_ino == os.stat(b).st_ino and os.stat(a).st_nlink == 2,
              "the hard links are kept, unchanged")
        check(read(ro).decode() == messy and stat.S_IMODE(os.stat(ro).st_mode) == 0o444, "the read-only file is unchanged")
        check(read(other).decode() == clean, "the other file is formatted all the same")

        # An edit saved while the file is being formatted is kept (the file is compared just
        # before the rename): the edit is written as soon as nomec has read the file. Should
        # nomec finish formatting before that (it takes about a second), the round is run again.
        big = os.path.join(d, "big.nome")
        edit = "# the user's edit\n" + messy
        for _ in range(3):
            write(big, "".join(f"group g{i}\ninstance i{i} m   endinstance\nendgroup\n" for i in range(60000)))
            fd = inotify(big, IN_CLOSE_NOWRITE)
            proc = subprocess.Popen([nomec, "fmt", "-i", "--max-file-size", "16M", big], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            for _ in events(fd, proc):
                write(big, edit)
                break
            os.close(fd)
            proc.wait()
            err = proc.stderr.read()
            if proc.returncode != 0 or read(big).decode() != edit:
                break
        check(proc.returncode == 2 and f"`{big}` changed since it was read" in err,
              f"the change is reported: exit {proc.returncode}: {err}")
        check(read(big).decode() == edit, "the edit is kept")
        check(not temps(d), f"no temporary files: {temps(d)}")


def case_signals(nomec, _corpus):
    cube = src("tests/mesh/testdata/cube_six_faces.nome")
    for sig in (signal.SIGINT, signal.SIGTERM):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "big.stl")
            write(out, "previous output")
            # An ASCII STL of about 50 MB: the temporary file exists for a few hundred ms, and
            # the signal is sent when it appears. Should the write end first, the round is run
            # again.
            for _ in range(3):
                fd = inotify(d, IN_CREATE)
                proc = subprocess.Popen([nomec, "--emit", "stl", "--stl-ascii", "--subdivide", "7", "-o", out, cube],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                seen = False
                for name in events(fd, proc):
                    if ".tmp." in name:
                        seen = True
                        proc.send_signal(sig)
                        break
                os.close(fd)
                proc.wait()
                if proc.returncode != 0:
                    break
                write(out, "previous output")
            check(seen, f"{sig.name}: the temporary file was seen")
            check(proc.returncode == -sig, f"{sig.name}: nomec ends by the signal (returncode {proc.returncode})")
            check(not temps(d), f"{sig.name}: no temporary file left: {temps(d)}")
            check(read(out) == b"previous output", f"{sig.name}: the previous output is intact")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=["output_is_input", "save", "fmt", "signals"])
    ap.add_argument("--nomec", required=True)
    ap.add_argument("--corpus", default=os.path.join(ROOT, "..", "shared", "corpus"))
    a = ap.parse_args()
    cases = {"output_is_input": case_output_is_input, "save": case_save, "fmt": case_fmt, "signals": case_signals}
    cases[a.case](a.nomec, a.corpus)
    if FAILURES:
        print(f"{len(FAILURES)} check(s) failed")
        return 1
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
