# Sourced by the scripts that unpack pinned Debian packages privately (scripts/radv, scripts/mesa-gl,
# scripts/intel-shim). debian_mirror prints the URI this machine's apt configuration uses for Debian's main
# archive (the one that serves bookworm), so no script names a host: deb822 .sources files first, then
# one-line sources.list entries. Prints nothing when apt has no Debian source.
debian_mirror() {
  local f uri
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    # One stanza per blank-line-separated block: the URI of a block whose Suites name bookworm.
    uri=$(awk 'BEGIN{RS=""; FS="\n"} {u=""; s=0; for (i=1;i<=NF;i++) {
             if ($i ~ /^URIs:/) {sub(/^URIs:[ \t]*/, "", $i); split($i, a, /[ \t]+/); u=a[1]}
             if ($i ~ /^Suites:/ && $i ~ /(^|[ \t])bookworm([ \t]|$)/) s=1 }
           if (s && u != "") {print u; exit} }' "$f")
    [ -n "$uri" ] && { echo "${uri%/}"; return 0; }
  done
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    uri=$(awk '$1 == "deb" && $0 ~ /[ \t]bookworm[ \t]/ { for (i=2;i<=NF;i++) if ($i ~ /^[a-z]+:\/\//) {print $i; exit} }' "$f")
    [ -n "$uri" ] && { echo "${uri%/}"; return 0; }
  done
  return 1
}
