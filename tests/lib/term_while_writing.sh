# Sourced by the command-line tests. term_while_writing DIR COMMAND...:
# runs COMMAND in the background (SIGINT at its default action: a
# background job ignores it), sends it SIGTERM once a temporary
# ("*.tmp.*", util/atomic_file.h) appears in DIR, i.e. while a file is
# being written, and prints "RC LEFT": its exit status and the temporaries
# left in DIR. RC 0 means it finished before the temporary was seen.
term_while_writing() {
  local dir=$1
  shift
  env --default-signal=INT "$@" &
  local pid=$!
  while kill -0 $pid 2>/dev/null && ! compgen -G "$dir/*.tmp.*" >/dev/null; do :; done
  kill -TERM $pid 2>/dev/null
  local rc=0
  wait $pid || rc=$?
  echo "$rc $(find "$dir" -name '*.tmp.*' 2>/dev/null | wc -l)"
}
