# The start the readme-*.sh scripts share; source it, without arguments, as their first command:
#   strict mode, the repository root as the working folder, `start_xvfb` (scripts/lib/xvfb.sh), `tag` from the
#   first argument (default: lavapipe; shifted off, so "$@" holds the extra diffract options) and a release build.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[1]}")/.."
source scripts/lib/xvfb.sh
tag=${1:-lavapipe}
shift || true
cargo build --release -q
