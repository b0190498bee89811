# The start the readme-*.sh scripts share; source it, without arguments, as their first command:
#   strict mode, the repository root as the working folder, `start_xvfb` (scripts/lib/xvfb.sh), `tag` from the
#   first argument (default: lavapipe; shifted off, so "$@" holds the extra diffract options) and a release build;
#   `d`, the release binary; `scratch`, a folder removed on exit (with the Xvfb server, if one was started); and
#   `run ARGS…`, which runs diffract with ARGS and appends the command and its output (scratch paths shortened)
#   to the file `$log` and the terminal.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[1]}")/.."
source scripts/lib/xvfb.sh
tag=${1:-lavapipe}
shift || true
cargo build --release -q
d=$PWD/target/release/diffract
scratch=$(mktemp -d)
xvfb=
trap 'rm -rf "$scratch"; [ -n "$xvfb" ] && kill "$xvfb" 2>/dev/null || true' EXIT
run() {
  echo "\$ diffract $*" | sed -e "s|$PWD/||g" -e "s|$scratch/||g" | tee -a "$log"
  "$d" "$@" 2>&1 | sed -e "s|$scratch/||g" | tee -a "$log"
}
