#!/usr/bin/env python3
"""Command-line tests of `nomec fmt` (run by ctest as format/cli): printing one file,
`-` (stdin), `--check` (lists files that would change, exit 1), `-i` (atomic in-place
rewrite, only changed files touched, no temp files left), refusal of files with syntax
errors (exit 1, file:line:col on stderr) and usage errors (exit 2)."""
import argparse
import os
import subprocess
import sys
import tempfile

FAILURES = []
MESSY = "group g\ninstance i m   endinstance\nendgroup\n"
CLEAN = "group g\n    instance i m endinstance\nendgroup\n"
BROKEN = "point p (0 0 0 endpoint\n"


def check(cond, what):
    if not cond:
        FAILURES.append(what)
        print(f"FAIL: {what}")


def run(nomec, args, stdin=None):
    p = subprocess.run([nomec, "fmt"] + args, input=stdin, capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def write(path, text):
    with open(path, "w", newline="") as f:
        f.write(text)


def read(path):
    with open(path, newline="") as f:
        return f.read()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--nomec", required=True)
    nomec = ap.parse_args().nomec
    with tempfile.TemporaryDirectory() as d:
        messy, clean, broken = (os.path.join(d, n) for n in ("messy.nome", "clean.nome", "broken.nome"))
        write(messy, MESSY)
        write(clean, CLEAN)
        write(broken, BROKEN)

        rc, out, err = run(nomec, [messy])
        check(rc == 0 and out == CLEAN and err == "", f"print one file: rc={rc} out={out!r} err={err!r}")
        check(read(messy) == MESSY, "printing must not modify the file")

        rc, out, err = run(nomec, ["-"], stdin=MESSY)
        check(rc == 0 and out == CLEAN, f"stdin: rc={rc} out={out!r}")

        rc, out, err = run(nomec, ["--check", messy, clean])
        check(rc == 1 and out == messy + "\n", f"--check lists the changed file: rc={rc} out={out!r}")
        rc, out, err = run(nomec, ["--check", clean])
        check(rc == 0 and out == "", f"--check on a clean file: rc={rc} out={out!r}")
        rc, out, err = run(nomec, ["--check", "-"], stdin=MESSY)
        check(rc == 1 and out == "<stdin>\n", f"--check on stdin: rc={rc} out={out!r}")

        clean_mtime = os.stat(clean).st_mtime_ns
        os.chmod(messy, 0o640)
        rc, out, err = run(nomec, ["-i", messy, clean])
        check(rc == 0 and out == "", f"-i: rc={rc} out={out!r} err={err!r}")
        check(read(messy) == CLEAN, "-i rewrote the messy file")
        check(os.stat(messy).st_mode & 0o777 == 0o640, "-i keeps the file's permissions")
        check(os.stat(clean).st_mtime_ns == clean_mtime, "-i leaves an unchanged file alone")
        check(sorted(os.listdir(d)) == ["broken.nome", "clean.nome", "messy.nome"],
              f"no temporary files left: {os.listdir(d)}")
        rc, out, err = run(nomec, ["--in-place", messy])
        check(rc == 0 and read(messy) == CLEAN, "--in-place is idempotent")

        rc, out, err = run(nomec, [broken])
        check(rc == 1 and out == "", f"syntax error refused: rc={rc} out={out!r}")
        check(err.startswith(broken + ":1:") and "error:" in err, f"error names file:line:col: {err!r}")
        rc, out, err = run(nomec, ["-i", broken])
        check(rc == 1 and read(broken) == BROKEN, "-i leaves a file with syntax errors untouched")
        rc, out, err = run(nomec, ["--check", broken, clean])
        check(rc == 1 and out == "", f"--check with a syntax error: rc={rc} out={out!r}")

        for args, what in ((["--check", "-i", messy], "--check with -i"),
                           ([messy, clean], "two files without -i/--check"),
                           ([], "no file"),
                           (["-i", "-"], "stdin in place"),
                           (["--check", "-", messy], "stdin with another file"),
                           ([os.path.join(d, "missing.nome")], "unreadable file"),
                           (["--bogus", messy], "unknown flag")):
            rc, out, err = run(nomec, args, stdin="")
            check(rc == 2 and err != "", f"usage error exits 2 ({what}): rc={rc} err={err!r}")
        p = subprocess.run([nomec], capture_output=True, text=True)
        check(p.returncode == 2, f"nomec without files still exits 2: rc={p.returncode}")
    if FAILURES:
        print(f"{len(FAILURES)} failure(s)")
        return 1
    print("all nomec fmt CLI checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
