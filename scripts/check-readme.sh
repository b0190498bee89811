#!/usr/bin/env bash
# Runs every complete `diffract …` command the documentation shows (README.md, ARCHITECTURE.md and docs/*.md; in
# backticks or after `$ ` in a code block), as written, in a scratch folder beside a link to assets/: any non-zero
# exit fails the script. A `$ diffract …` line in a ```console block is followed by what it prints: there the
# output (stderr and stdout as they interleave) must be those lines, numbers within 1e-9 relative (durations,
# a number before `ms` or `s`, excepted). Commands with
# placeholders (FILE, SCENE, N, …, [optional parts], a|b choices, the user's own files) and `view` without
# --frames (it waits for a window to close) are listed as skipped. A command still running after the time limit
# (default 120 s per command; the README's longest, FLSS profiles at 800², take many minutes on lavapipe) is
# stopped and reported as cut: it was accepted and ran that long without an error.
# Usage: scripts/check-readme.sh [SECONDS]   (needs what scripts/setup-debian.sh installs; builds the release binary)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/xvfb.sh
root=$PWD
limit=${1:-120}

cargo build --release --quiet
work=$(mktemp -d)
trap 'rm -rf "$work"; [ -n "${xvfb:-}" ] && kill "$xvfb" 2>/dev/null || true' EXIT
if [ -z "${DISPLAY:-}" ] && command -v Xvfb >/dev/null; then
  start_xvfb 95
fi
ln -s "$root/assets" "$work/assets"
# The README's own outputs (docs/images, docs/profile) are written into a copy, not over the repository's.
cp -r "$root/docs" "$work/docs"
mkdir -p "$work/bin" && ln -s "$root/target/release/diffract" "$work/bin/diffract"
export PATH="$work/bin:$PATH" DIFFRACT_CACHE="$work/cache"

# Commands: backticked spans, and code-block lines starting with "diffract" or "$ diffract", joined over trailing
# backslashes. A bare command name in prose (`diffract map`) is not a command.
mapfile -t commands < <(python3 - README.md ARCHITECTURE.md docs/*.md <<'PY'
import re, sys
found = []
for name in sys.argv[1:]:
    text = open(name, encoding="utf-8").read()
    for block in re.findall(r"```[^\n]*\n(.*?)```", text, re.S):
        lines = re.sub(r"\s*\\\n\s*", " ", block).splitlines()
        # In a table of commands, two spaces part a command from its description.
        found += [re.split(r"\s{2,}", l.removeprefix("$ ").strip())[0] for l in lines if l.startswith(("$ diffract ", "diffract "))]
    text = re.sub(r"```.*?```", "", text, flags=re.S)
    found += [c.strip() for c in re.findall(r"`(diffract [^`]+)`", text.replace("\n", " "))]
seen = set()
for c in found:
    c = re.sub(r"\s+", " ", c)
    # A command's bare name (`diffract map`) names it in prose; a window title is not a command.
    if not re.match(r"diffract [a-z]+ ", c + " ") or (len(c.split()) == 2 and c != "diffract devices"):
        continue
    if c not in seen:
        seen.add(c)
        print(c)
PY
)

placeholder='(\.\.\.|…|\[|\||<|\b(FILE|SCENE|NAME|KIND|N|W|H|D|DEG|F\.png|F\.obj|F\.gsf|F\.exr|NNNN)\b|scan\.|my-scene|mine\.)'
ran=0 skipped=0 cut=0 failures=0
for command in "${commands[@]}"; do
  if [[ $command =~ $placeholder ]] || { [[ $command == "diffract view"* ]] && [[ $command != *--frames* ]]; }; then
    echo "skip  $command"
    skipped=$((skipped + 1))
    continue
  fi
  start=$SECONDS
  status=0
  (cd "$work" && eval "timeout --kill-after=10 $limit $command") >"$work/log" 2>&1 || status=$?
  if [ "$status" -eq 0 ]; then
    echo "ok    $command ($((SECONDS - start)) s)"
    ran=$((ran + 1))
  elif [ "$status" -eq 124 ] && ! grep -q '^error' "$work/log"; then
    echo "cut   $command (still running without an error after $limit s)"
    cut=$((cut + 1))
  else
    echo "FAIL  $command"
    sed 's/^/      /' "$work/log" | tail -5
    failures=$((failures + 1))
  fi
done
# The console examples: each command's output against the lines the page shows after it.
examples=0
if ! examples=$(cd "$work" && python3 - "$root" README.md ARCHITECTURE.md docs/*.md <<'PY'
import os, re, subprocess, sys
root, pages = sys.argv[1], sys.argv[2:]
number = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")

def tokens(line):
    """The line's numbers (durations left out) and the text between them."""
    line = re.sub(r"[-+]?\d+(?:\.\d+)?\s*(?:ms|s)\b", "<duration>", line)
    return [float(t) for t in number.findall(line)], number.sub("#", line).split()

def same(expected, actual):
    (en, et), (an, at) = tokens(expected), tokens(actual)
    return et == at and len(en) == len(an) and all(abs(a - e) <= 1e-9 * max(abs(e), 1e-300) or a == e
                                                   for e, a in zip(en, an))

failed = ran = 0
for page in pages:
    text = open(os.path.join(root, page), encoding="utf-8").read()
    for block in re.findall(r"```console\n(.*?)```", text, re.S):
        examples, current = [], None
        for line in re.sub(r"\s*\\\n\s*", " ", block).splitlines():
            if line.startswith("$ "):
                current = (line[2:].strip(), [])
                examples.append(current)
            elif current is not None:
                current[1].append(line)
        for command, expected in examples:
            out = subprocess.run(command, shell=True, capture_output=False, stdout=subprocess.PIPE,
                                 stderr=subprocess.STDOUT, text=True, timeout=600).stdout.splitlines()
            ran += 1
            bad = len(out) != len(expected) or not all(same(e, a) for e, a in zip(expected, out))
            if bad:
                failed += 1
                print(f"FAIL  {page}: `{command}` printed what the page does not show:", file=sys.stderr)
                for e, a in zip(expected + [""] * len(out), out + [""] * len(expected)):
                    if not same(e, a):
                        print(f"      page:   {e}\n      binary: {a}", file=sys.stderr)
                        break
print(ran)
sys.exit(1 if failed else 0)
PY
); then
  failures=$((failures + 1))
fi
echo "check-readme: $ran command(s) ran, $cut cut at $limit s, $skipped skipped, $failures failed; ${examples:-0} console example(s) compared with their output"
[ "$failures" -eq 0 ]
