#!/usr/bin/env bash
# The robot models users have: example-robot-data (BSD-3-Clause; each robot's
# meshes keep their own licence, see its package) from PyPI, into
# third_party/example-robot-data/ (not committed). Idempotent: does nothing
# when that version is there. Only the wheel's robots/ folder is kept.
#   scripts/setup/fetch_robots.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
version=4.3.0
dest=third_party/example-robot-data
[[ -f "$dest/VERSION" && "$(cat "$dest/VERSION")" == "$version" ]] && exit 0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 -m pip download --quiet --no-deps --only-binary=:all: "example-robot-data==$version" -d "$tmp" ||
  { echo "fetch_robots: could not download example-robot-data $version from PyPI" >&2; exit 1; }
python3 - "$tmp" "$dest" <<'PY'
import glob, os, shutil, sys, zipfile
tmp, dest = sys.argv[1], sys.argv[2]
wheel = glob.glob(os.path.join(tmp, "*.whl"))[0]
prefix = "cmeel.prefix/share/example-robot-data/"
shutil.rmtree(dest, ignore_errors=True)
with zipfile.ZipFile(wheel) as z:
    for name in z.namelist():
        if name.startswith(prefix + "robots/") and not name.endswith("/"):
            out = os.path.join(dest, name[len(prefix):])
            os.makedirs(os.path.dirname(out), exist_ok=True)
            with z.open(name) as src, open(out, "wb") as dst:
                shutil.copyfileobj(src, dst)
PY
echo "$version" > "$dest/VERSION"
echo "fetch_robots: example-robot-data $version in $dest/robots"
