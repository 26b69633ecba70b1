# The bus key for the launch scripts (source it).
#   igms_new_key FILE       writes 32 random bytes as 64 hex digits, readable by
#                           its owner only (mode 0600), the format every
#                           program's --key-file / IGMS_KEY_FILE reads
#                           (bus/bus_key.h). Created with O_EXCL (bash's
#                           noclobber): never over an existing file, never
#                           through a planted symbolic link.
#   igms_private_folder DIR makes DIR (mode 0700) or checks the one there: a
#                           directory, not a link, owned by this user, closed
#                           to others. A key lives only in such a folder: a
#                           guessable name in a shared /tmp is someone else's
#                           to plant first.
igms_new_key() {
  local file=$1
  [[ -e $file || -L $file ]] && { echo "bus key: $file exists; not overwritten" >&2; return 1; }
  (set -o noclobber && umask 077 && { od -An -N32 -tx1 -v /dev/urandom | tr -d ' \n' && echo; } > "$file") ||
    { echo "bus key: cannot create $file (created by someone else meanwhile?)" >&2; return 1; }
}

igms_private_folder() {
  local dir=$1
  mkdir -m 700 "$dir" 2>/dev/null || true
  if [[ -L $dir || ! -d $dir ]]; then
    echo "bus key: $dir is not a folder of its own (a link or a file is there); remove it or set XDG_RUNTIME_DIR" >&2
    return 1
  fi
  local owner mode
  owner=$(stat -c %u "$dir")
  mode=$(stat -c %a "$dir")
  if [[ $owner != "$(id -u)" ]]; then
    echo "bus key: $dir is owned by uid $owner, not by this user (uid $(id -u)); someone made it first" >&2
    return 1
  fi
  if [[ $mode != 700 ]]; then
    echo "bus key: $dir is open to others (mode $mode); it must be 700 (chmod 700 it, or remove it)" >&2
    return 1
  fi
}

# Exports IGMS_KEY_FILE for the processes a script starts: the caller's own
# key when it set one, else a new key in a private folder of its own under
# TMPDIR (mktemp -d: a new 0700 folder with an unguessable name; removed by
# igms_drop_key).
igms_key_dir=""
igms_use_key() {
  [[ -n ${IGMS_KEY_FILE:-} ]] && return 0
  igms_key_dir=$(mktemp -d "${TMPDIR:-/tmp}/igms-key.XXXXXX")
  igms_new_key "$igms_key_dir/bus.key"
  export IGMS_KEY_FILE=$igms_key_dir/bus.key
}
igms_drop_key() {
  [[ -n $igms_key_dir ]] && rm -rf "$igms_key_dir"
  igms_key_dir=""
}
