#!/usr/bin/python3
"""The cost of rendering through Python against the same render through the `uvr` program (the goal: no more).

    PYTHONPATH=build/python /usr/bin/python3 bench/python_vs_program.py [--algo havs] [--backend emu] [--rounds 5]

One run on the built-in torus at 512 x 512. Rounds alternate the two so both see the same state of the machine (odd
rounds start with the program, even rounds with Python), and the medians of the per-round ratios are reported:
  - render: the render's own time, the program's (`uvr render --json`: renderer made and frame rendered, its "seconds")
    against uvr.render()'s wall time in the interpreter (the same work, plus handing the image to NumPy);
  - process: a whole `uvr render ... --out x.npy` against a whole `python3 -c "import uvr; ...render..."` (start-up,
    scene set-up, render; the program also writes its file).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import uvr

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--uvr", default=os.path.join(HERE, "build", "bench", "uvr"))
    ap.add_argument("--source", default="builtin:torus")
    ap.add_argument("--algo", default="havs")
    ap.add_argument("--backend", default="emu")
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--rounds", type=int, default=5)
    a = ap.parse_args()
    out = os.path.join(tempfile.mkdtemp(), "x.npy")
    cli = [a.uvr, "render", a.source, "--algo", a.algo, "--size", f"{a.size}x{a.size}", "--out", out, "--json"]
    if a.algo != "reference":
        cli += ["--backend", a.backend]
    options = {} if a.algo == "reference" else {"backend": a.backend}
    script = (f"import uvr; s = uvr.Scene({a.source!r}, size=({a.size}, {a.size})); "
              f"uvr.render(s, {a.algo!r}, **{options!r})")
    scene = uvr.Scene(a.source, size=(a.size, a.size))
    uvr.render(scene, a.algo, **options)  # warm: the first GL context, the page cache
    render_ratio, process_ratio, rows = [], [], []
    def program():
        t0 = time.perf_counter()
        done = subprocess.run(cli, check=True, stdout=subprocess.PIPE)
        return json.loads(done.stdout)["seconds"], time.perf_counter() - t0

    def python():
        t0 = time.perf_counter()
        uvr.render(scene, a.algo, **options)
        render = time.perf_counter() - t0
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", script], check=True, env=dict(os.environ))
        return render, time.perf_counter() - t0

    for r in range(a.rounds):
        if r % 2 == 0:
            program_render, program_process = program()
            python_render, python_process = python()
        else:
            python_render, python_process = python()
            program_render, program_process = program()
        render_ratio.append(python_render / program_render)
        process_ratio.append(python_process / program_process)
        rows.append((program_render, python_render, program_process, python_process))
        print(f"round {r + 1}: render {program_render * 1e3:.1f} ms (program) / {python_render * 1e3:.1f} ms "
              f"(Python); process {program_process:.2f} s / {python_process:.2f} s", flush=True)
    print(f"{a.source} {a.algo} on {a.backend}, {a.size}x{a.size}, {os.cpu_count()} threads, {a.rounds} rounds: "
          f"Python / program, render {statistics.median(render_ratio):.3f} (range {min(render_ratio):.3f}-"
          f"{max(render_ratio):.3f}), whole process {statistics.median(process_ratio):.3f} (range "
          f"{min(process_ratio):.3f}-{max(process_ratio):.3f})")


if __name__ == "__main__":
    main()
