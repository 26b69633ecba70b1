#!/usr/bin/env bash
# The launch scripts' key files (issue 44, item 6): a key is made with O_EXCL in
# a private 0700 folder, never over a file or through a link someone planted,
# and a folder someone else made (a link, another owner, open to others) is
# refused with a one-line reason.
#   tests/unit/bus_key_script_test.sh
set -uo pipefail
cd "$(dirname "$0")/../.."
source scripts/lib/bus_key.sh
work=$(mktemp -d /tmp/igms-key-script.XXXXXX)
trap 'rm -rf "$work"' EXIT
failures=0
check() {  # DESCRIPTION COMMAND...: the command must succeed
  local what=$1
  shift
  if "$@"; then echo "ok: $what"; else echo "FAIL: $what"; failures=$((failures + 1)); fi
}
refused() {  # DESCRIPTION EXPECTED_TEXT COMMAND...: the command must fail and say EXPECTED_TEXT
  local what=$1 text=$2 out
  shift 2
  if out=$("$@" 2>&1); then
    echo "FAIL: $what (it succeeded)"
    failures=$((failures + 1))
  elif [[ $out != *"$text"* ]]; then
    echo "FAIL: $what (said: $out)"
    failures=$((failures + 1))
  else
    echo "ok: $what ($out)"
  fi
}
mode_of() { stat -c %a "$1"; }

# A private folder and a key in it.
check "a new folder is made private" igms_private_folder "$work/own"
check "its mode is 700" test "$(mode_of "$work/own")" = 700
check "the same folder again is fine" igms_private_folder "$work/own"
check "a new key" igms_new_key "$work/own/bus.key"
check "the key's mode is 600" test "$(mode_of "$work/own/bus.key")" = 600
check "the key is 64 hex digits" grep -Eq '^[0-9a-f]{64}$' "$work/own/bus.key"
before=$(cat "$work/own/bus.key")
refused "a key is never overwritten" "exists; not overwritten" igms_new_key "$work/own/bus.key"
check "the key is unchanged" test "$(cat "$work/own/bus.key")" = "$before"

# Planted links: the key is not written through them.
echo "victim" > "$work/victim"
ln -s "$work/victim" "$work/own/planted.key"
refused "a key path planted as a link" "exists" igms_new_key "$work/own/planted.key"
check "the link's target is untouched" test "$(cat "$work/victim")" = victim
ln -s "$work/nowhere" "$work/own/dangling.key"
refused "a key path planted as a dangling link" "exists" igms_new_key "$work/own/dangling.key"
check "nothing was made where the dangling link points" test ! -e "$work/nowhere"
# The O_EXCL itself (no check before it): a link appearing between the check and the open.
out=$(cd "$work/own" && (set -o noclobber && echo x > planted.key) 2>&1) && { echo "FAIL: noclobber wrote through a link"; failures=$((failures + 1)); } || echo "ok: O_EXCL refuses a link ($out)"

# Folders someone else made first.
mkdir "$work/real" && chmod 700 "$work/real"
ln -s "$work/real" "$work/linked"
refused "a folder planted as a link" "not a folder of its own" igms_private_folder "$work/linked"
mkdir -m 777 "$work/open"
refused "a folder open to others" "open to others (mode 777)" igms_private_folder "$work/open"
touch "$work/file"
refused "a file where the folder goes" "not a folder of its own" igms_private_folder "$work/file"
if [[ $(id -u) -eq 0 ]] && id nobody > /dev/null 2>&1; then
  mkdir -m 700 "$work/theirs" && chown nobody "$work/theirs"
  refused "a folder another user owns" "owned by uid $(id -u nobody)" igms_private_folder "$work/theirs"
else
  echo "skip: a folder another user owns (needs root to make one)"
fi

# bus.sh keeps its key in such a folder: its path names the user's folder, not /tmp/igms-bus-NAME.key.
path=$(XDG_RUNTIME_DIR=$work IGMS_BUS=keytest bash -c 'source scripts/lib/bus_key.sh; grep -o "key_folder=.*" scripts/sessions/bus.sh | head -1')
check "bus.sh's key folder is per user" grep -q 'igms-bus-$(id -u)' <<< "$path"
refused "bus.sh refuses a bus name that is a path" "is a name" env IGMS_BUS=../x scripts/sessions/bus.sh key

if ((failures > 0)); then
  echo "bus_key_script_test: $failures failed"
  exit 1
fi
echo "bus_key_script_test: all passed"
