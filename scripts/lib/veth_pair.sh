# Two network namespaces joined by a veth pair: two "hosts" on one machine for a test (sourced).
#   igms_veth_pair NS_A NS_B DEV_A DEV_B PREFIX   (PREFIX: a /24 such as 10.77.0; A is .1, B is .2)
# Each namespace gets lo and its end of the link up, multicast routed over the link (ttl=1 reaches the
# other host only). The caller deletes the namespaces (ip netns del), which deletes the link.
igms_veth_pair() {
  local a=$1 b=$2 dev_a=$3 dev_b=$4 prefix=$5
  ip netns add "$a"
  ip netns add "$b"
  ip link add "$dev_a" type veth peer name "$dev_b"
  ip link set "$dev_a" netns "$a"
  ip link set "$dev_b" netns "$b"
  ip -n "$a" addr add "$prefix.1/24" dev "$dev_a"
  ip -n "$b" addr add "$prefix.2/24" dev "$dev_b"
  local ns dev
  for pair in "$a:$dev_a" "$b:$dev_b"; do
    ns=${pair%%:*} dev=${pair##*:}
    ip -n "$ns" link set lo up
    ip -n "$ns" link set "$dev" up
    ip -n "$ns" link set "$dev" multicast on
    ip -n "$ns" route add 224.0.0.0/4 dev "$dev"
  done
}
