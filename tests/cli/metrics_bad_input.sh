#!/usr/bin/env bash
# `al-refine metrics`: bad input gives a one-line error naming the file and exit code 2; a missing
# --dir is a usage error (1); a directory with nothing to score still succeeds and says why.
set -u
BIN="$1"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$BIN" metrics >/dev/null 2>&1
[ $? -eq 1 ] || fail "missing --dir should exit 1"

"$BIN" metrics --dir "$TMP/nope" --out "$TMP/o1" 2>"$TMP/err1"
[ $? -eq 2 ] || fail "non-existent directory should exit 2"
grep -q "$TMP/nope" "$TMP/err1" || fail "error does not name the directory: $(cat "$TMP/err1")"
[ "$(wc -l < "$TMP/err1")" -eq 1 ] || fail "error is not one line"

# Corrupt SAM JSON: exit 2, names the file, no outputs left behind.
mkdir -p "$TMP/s/masks" "$TMP/s/sam/after"
printf '[{"segmentation": ' > "$TMP/s/masks/v.json"
printf '[]' > "$TMP/s/sam/after/v.json"
"$BIN" metrics --dir "$TMP/s" --out "$TMP/o2" 2>"$TMP/err2"
[ $? -eq 2 ] || fail "corrupt JSON should exit 2"
grep -q "v.json" "$TMP/err2" || fail "error does not name the JSON file: $(cat "$TMP/err2")"
[ ! -e "$TMP/o2/report.json" ] || fail "report.json written on failure"

# Corrupt depth PNG: exit 2, names the file.
mkdir -p "$TMP/d/depth/before" "$TMP/d/depth/after"
printf 'garbage' > "$TMP/d/depth/before/v.png"
printf 'garbage' > "$TMP/d/depth/after/v.png"
"$BIN" metrics --dir "$TMP/d" --out "$TMP/o3" 2>"$TMP/err3"
[ $? -eq 2 ] || fail "corrupt depth PNG should exit 2"
grep -q "v.png" "$TMP/err3" || fail "error does not name the PNG: $(cat "$TMP/err3")"

# Empty scene directory: ok, every metric skipped with a reason in report.json.
mkdir -p "$TMP/empty"
"$BIN" metrics --dir "$TMP/empty" --out "$TMP/o4" >/dev/null || fail "empty scene should succeed"
[ -f "$TMP/o4/report.json" ] || fail "no report.json"
grep -q '"skipped"' "$TMP/o4/report.json" || fail "report.json lacks the skipped list"
grep -q '"sim_sam"' "$TMP/o4/report.json" || fail "report.json does not say sim_sam was skipped"
# Detector folders: absent at the standard path = empty detections and a warning (the released
# evaluator); absent where the user named it = a typo, exit 2 naming the folder.
mkdir -p "$TMP/g/masks"
python3 - "$TMP/g/masks/v.png" <<'PY' || fail "could not write the test mask"
import struct, sys, zlib  # an 8x8 white 8-bit grey PNG, without third-party modules
def chunk(t, d): return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d))
raw = b''.join(b'\x00' + b'\xff' * 8 for _ in range(8))
png = b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', 8, 8, 8, 0, 0, 0, 0))
open(sys.argv[1], 'wb').write(png + chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))
PY
"$BIN" metrics --dir "$TMP/g" --out "$TMP/o5" 2>"$TMP/err5" >/dev/null || fail "absent default detector folders should succeed"
grep -q "no detector mask folder" "$TMP/err5" "$TMP/o5/report.json" || fail "no warning about the absent folders"
"$BIN" metrics --dir "$TMP/g" --seg-before gsam2/befor/mask --out "$TMP/o6" 2>"$TMP/err6" >/dev/null
[ $? -eq 2 ] || fail "a named detector folder that does not exist should exit 2"
grep -q "gsam2/befor/mask" "$TMP/err6" || fail "error does not name the folder: $(cat "$TMP/err6")"
[ ! -e "$TMP/o6/report.json" ] || fail "report.json written on failure"
echo "ok"
