# Sourced by the scripts that write a table into BENCHMARKS.md (through benches/common.sh, or
# alone where nothing needs building or a display): the section writer and the figures' words.

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

# fps MS: frames a second of a frame of MS milliseconds, or – where there is no figure.
fps() { awk -v ms="$1" 'BEGIN { if (ms + 0 > 0) printf "%.0f", 1000 / ms; else print "–" }'; }
