# The bus key for the launch scripts (source it): igms_new_key FILE writes 32
# random bytes as 64 hex digits, readable by its owner only (mode 0600), the
# format every program's --key-file / IGMS_KEY_FILE reads (bus/bus_key.h).
igms_new_key() {
  local file=$1
  [[ -e $file ]] && { echo "bus key: $file exists; not overwritten" >&2; return 1; }
  (umask 077 && od -An -N32 -tx1 -v /dev/urandom | tr -d ' \n' > "$file" && echo >> "$file")
}

# Exports IGMS_KEY_FILE for the processes a script starts: the caller's own
# key when it set one, else a new key in a private folder of its own under
# TMPDIR (removed by igms_drop_key).
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
