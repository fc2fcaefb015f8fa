#!/usr/bin/env bash
# uvr gpu-check keeps what it measured (docs/gpu.md): stopped by SIGTERM after its first run, OUT/gpu-check.json is
# valid JSON holding that run, `complete` false; past --time-limit no new run starts and the files say why; a scene
# that cannot be read is kept with its error and the other runs go on; each run's frame equals the CPU emulation's bit
# for bit (on llvmpipe the emulation is the device's arithmetic); with framebuffer fetch hidden (UVR_GL_HIDE_EXTENSIONS)
# HAVS and VICP take the image route and still give those bits; with the image route hidden too, both are skipped with
# the reason and the ray caster runs. On llvmpipe.
# Usage: tests/gpu_check_stop.sh UVR_BINARY
set -euo pipefail
uvr=$1
# shellcheck source=tests/script_support.sh
source "$(dirname "$0")/script_support.sh"
runs() {  # DIR: the number of runs in DIR/gpu-check.json (fails on invalid JSON)
  python3 -c 'import json, sys; print(len(json.load(open(sys.argv[1] + "/gpu-check.json"))["runs"]))' "$1"
}
field() {  # DIR KEY: the JSON value of KEY
  python3 -c 'import json, sys; print(json.dumps(json.load(open(sys.argv[1] + "/gpu-check.json")).get(sys.argv[2])))' \
    "$1" "$2"
}
quick=(builtin:torus-small --gpu llvmpipe --grid 0 --warmup 0)

# SIGTERM once the first run is written: many runs are left to do (eight sizes, twenty frames each).
"$uvr" gpu-check "${quick[@]}" --sizes 24,24,24,24,24,24,24,24 --repeat 20 --out "$tmp/term" >/dev/null 2>&1 &
pid=$!
for _ in $(seq 1 600); do
  [ -s "$tmp/term/gpu-check.json" ] && [ "$(runs "$tmp/term")" -ge 1 ] && break
  sleep 0.1
done
kill -TERM "$pid" 2>/dev/null || fail "the check ended before it could be stopped"
wait "$pid" && fail "a check stopped by SIGTERM exited 0"
n=$(runs "$tmp/term") || fail "gpu-check.json is not valid JSON after SIGTERM"
[ "$n" -ge 1 ] || fail "gpu-check.json holds no run after SIGTERM"
[ "$(field "$tmp/term" complete)" = false ] || fail "a stopped check says it is complete"
python3 -c 'import json, sys; r = json.load(open(sys.argv[1]))["runs"][0]; sys.exit(0 if "rmse" in r else 1)' \
  "$tmp/term/gpu-check.json" || fail "the first run has no measures"

# --time-limit: no run starts once it has passed; the files are finished and say why.
"$uvr" gpu-check "${quick[@]}" --sizes 24 --repeat 1 --time-limit 0.000001 --out "$tmp/limit" >/dev/null ||
  fail "a check stopped by its time limit failed"
[ "$(runs "$tmp/limit")" -eq 0 ] || fail "a run started after the time limit"
[ "$(field "$tmp/limit" complete)" = false ] || fail "a check stopped by its time limit says it is complete"
field "$tmp/limit" stopped | grep -q "time limit" || fail "the JSON does not say the time limit stopped it"
grep -q "Stopped: the time limit" "$tmp/limit/index.html" || fail "the page does not say the time limit stopped it"

# A scene that cannot be read: kept with its error; the mesh's runs stand and the check completes.
"$uvr" gpu-check "${quick[@]}" --sizes 24 --repeat 1 --volume "$tmp/none.vti" --out "$tmp/error" >/dev/null ||
  fail "a check with a missing volume failed"
[ "$(field "$tmp/error" complete)" = true ] || fail "the check did not complete"
python3 - "$tmp/error/gpu-check.json" <<'PY' || fail "the missing volume's run is not kept with its error"
import json, sys
runs = json.load(open(sys.argv[1]))["runs"]
errors = [r for r in runs if "error" in r]
assert len(errors) == 1 and "none.vti" in errors[0]["error"], errors
assert any("rmse" in r for r in runs)
PY
# On llvmpipe the emulation is the device's own arithmetic: every run's frame equals it bit for bit.
python3 - "$tmp/error/gpu-check.json" <<'PY' || fail "llvmpipe's frames differ from the emulation's"
import json, sys
for r in json.load(open(sys.argv[1]))["runs"]:
    if "error" in r:
        continue
    d = r["gpu_vs_emulation"]
    assert d["rmse"] == 0 and d["max_abs"] == 0 and d["pixels_differing"] == 0, (r["label"], d)
    assert r["emulation"]["rmse"] == r["rmse"], r["label"]
PY
# Framebuffer fetch hidden: HAVS and VICP through the image route (no interlock on llvmpipe), the emulation's bits.
UVR_GL_HIDE_EXTENSIONS=GL_EXT_shader_framebuffer_fetch "$uvr" gpu-check "${quick[@]}" --sizes 24 --repeat 1 \
  --out "$tmp/images" >/dev/null || fail "the check with framebuffer fetch hidden failed"
python3 - "$tmp/images/gpu-check.json" <<'PY' || fail "the image route did not run or differs from the emulation"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["kbuffer"]["path"].startswith("image load/store"), j["kbuffer"]
runs = {r["label"]: r for r in j["runs"]}
for label in ("havs-gl-k6", "vicp-gl-mpvonc", "raycast-gl-post"):
    assert runs[label]["gpu_vs_emulation"]["pixels_differing"] == 0, (label, runs[label])
PY
# Fetch and the image route hidden: HAVS and VICP skipped with the missing extensions named, the ray caster runs, the
# check completes.
UVR_GL_HIDE_EXTENSIONS=GL_EXT_shader_framebuffer_fetch,UVR_llvmpipe_image_route "$uvr" gpu-check "${quick[@]}" \
  --sizes 24 --repeat 1 --out "$tmp/none" >/dev/null || fail "the check with no route for HAVS and VICP failed"
python3 - "$tmp/none/gpu-check.json" <<'PY' || fail "HAVS and VICP were not skipped with the reason, or the rest failed"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["complete"] is True
skipped = [r for r in j["runs"] if "skipped" in r]
assert sorted(r["label"] for r in skipped) == ["havs", "vicp"], skipped
assert all("GL_EXT_shader_framebuffer_fetch" in r["skipped"] for r in skipped)
assert any(r.get("label") == "raycast-gl-post" and "rmse" in r for r in j["runs"])
PY
echo "gpu-check: valid after SIGTERM, stopped by its time limit, a failed scene kept, llvmpipe the emulation, both routes and the skip; every check passed"
