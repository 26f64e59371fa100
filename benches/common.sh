# Shared by benches/frames.sh and benches/rays.sh (sourced from the repository root): builds
# the release binary, makes sure there is a display (Xvfb on :78 when $DISPLAY is unset), and
# writes a measured table into BENCHMARKS.md between its markers.

cargo build --release --quiet
if [ -z "${DISPLAY:-}" ]; then
    Xvfb :78 -screen 0 1400x900x24 >/dev/null 2>&1 &
    XVFB=$!
    trap 'kill $XVFB 2>/dev/null || true' EXIT
    export DISPLAY=:78
    sleep 2
fi
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
bin=${CARGO_TARGET_DIR:-./target}/release/voxcast

# write_section NAME HEADING FILE: FILE's text (which starts with <!-- bench:NAME --> and ends
# with <!-- /bench:NAME -->) replaces that section of BENCHMARKS.md, or is appended under
# "## HEADING".
write_section() {
    python3 - "$1" "$2" "$3" <<'PY'
import re, sys
name, heading, table = sys.argv[1], sys.argv[2], open(sys.argv[3]).read().strip()
path = "BENCHMARKS.md"
text = open(path).read()
pattern = re.compile(r"<!-- bench:%s -->.*?<!-- /bench:%s -->" % (name, name), re.S)
if pattern.search(text):
    text = pattern.sub(lambda _: table, text)
else:
    text = text.rstrip() + "\n\n## " + heading + "\n\n" + table + "\n"
open(path, "w").write(text)
PY
}
