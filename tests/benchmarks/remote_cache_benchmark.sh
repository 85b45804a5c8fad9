#!/usr/bin/env bash
# The shared compile cache (pack --remote-cache) on a project of N shader files (generate_shader_project.sh):
# - per server (nginx with WebDAV PUT, redis-server; each started here on a free loopback port): checkout A
#   packs cold into the empty server; checkout B, a copy at another path with an empty local cache, packs
#   from the server (goal: no compile, the same bytes, <= 15 % of the cold pack). Entries signed with a team
#   key (STATEPACK_CACHE_KEY); once more over HTTP unsigned, where B validates every fetched module;
# - the server killed before B's pack (goal: <= one time-out + 10 % over a pack without any cache);
# - two shards on two processes into a shared directory (file:), then --no-compile from it (goal: each
#   shard compiles 50 +- 10 %, the assembly compiles nothing, the same bytes).
# Prints a Markdown table. Every archive is compared with a pack without a cache.
# Usage: remote_cache_benchmark.sh <statepack> <repository root> [N=1000] [real|small]
# Run it through CMake: cmake --build build --target bench_remote_cache
set -euo pipefail
statepack=$1 root=$2 count=${3:-1000} kind=${4:-real}
work=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -9 "$p" 2> /dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
bash "$(dirname "$0")/generate_shader_project.sh" "$root" "$work/a" "$count" "$kind"
mkdir -p "$work/elsewhere" && cp -r "$work/a" "$work/elsewhere/b"
free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
wait_port() { for _ in $(seq 500); do (: < "/dev/tcp/127.0.0.1/$1") 2> /dev/null && return 0; sleep 0.01; done; return 1; }

# Wall milliseconds of one pack of checkout $1 to $2 (more arguments follow); sets $ms and $report.
pack() {
  local dir=$1 out=$2
  shift 2
  local start end
  start=$(date +%s%N)
  report=$(cd "$dir" && "$statepack" pack -i project.json -o "$out" --vulkan --time-report "$@" 2>&1 > /dev/null)
  end=$(date +%s%N)
  ms=$(((end - start) / 1000000))
}
same() { cmp -s "$work/plain.spk" "$1" || { echo "FAIL: $1 differs from a pack without a cache"; exit 1; }; }
misses() { sed -n 's/.*cache: [0-9]* hits, \([0-9]*\) misses.*/\1/p' <<< "$report"; }
share() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f %%", 100 * a / b }'; }

pack "$work/a" "$work/plain.spk"
plain_ms=$ms
rows=()

port=$(free_port)
mkdir -p "$work/nginx/root"
cat > "$work/nginx/nginx.conf" << CONF
daemon off; master_process off; pid $work/nginx/nginx.pid; error_log $work/nginx/error.log;
events { worker_connections 256; }
http { access_log off; client_body_temp_path $work/nginx/body; proxy_temp_path $work/nginx/proxy;
  fastcgi_temp_path $work/nginx/fastcgi; uwsgi_temp_path $work/nginx/uwsgi; scgi_temp_path $work/nginx/scgi;
  server { listen 127.0.0.1:$port; root $work/nginx/root; client_max_body_size 256m;
    location / { dav_methods PUT; create_full_put_path on; } } }
CONF
nginx -e "$work/nginx/error.log" -p "$work/nginx" -c "$work/nginx/nginx.conf" &
nginx_pid=$!
pids+=("$nginx_pid")
wait_port "$port"
redis_port=$(free_port)
redis-server --port "$redis_port" --bind 127.0.0.1 --save '' --appendonly no --dir "$work" > /dev/null &
pids+=($!)
wait_port "$redis_port"

export STATEPACK_CACHE_KEY=benchmark-team-key
for url in "http://127.0.0.1:$port/cache" "redis://127.0.0.1:$redis_port" "http://127.0.0.1:$port/unsigned"; do
  name="${url%%:*} (signed)"
  [[ $url == */unsigned ]] && name="http (unsigned)" && unset STATEPACK_CACHE_KEY
  rm -rf "$work/cache-a" "$work/cache-b"
  pack "$work/a" "$work/cold.spk" --cache-dir "$work/cache-a" --remote-cache "$url"
  cold_ms=$ms
  same "$work/cold.spk"
  pack "$work/elsewhere/b" "$work/remote.spk" --cache-dir "$work/cache-b" --remote-cache "$url"
  same "$work/remote.spk"
  [[ $(misses) == 0 ]] || { echo "FAIL: checkout B compiled $(misses) times from $name"; exit 1; }
  rows+=("| $name: A cold into the empty server | $cold_ms ms | $(share "$cold_ms" "$plain_ms") |")
  rows+=("| $name: B (another path, empty local cache) from the server, 0 compiles | $ms ms | $(share "$ms" "$cold_ms") of A's cold |")
done

kill -9 "$nginx_pid"
wait "$nginx_pid" 2> /dev/null || true
rm -rf "$work/cache-b"
pack "$work/elsewhere/b" "$work/dead.spk" --cache-dir "$work/cache-b" --remote-cache "http://127.0.0.1:$port/cache"
same "$work/dead.spk"
grep -q "not asked again" <<< "$report" || { echo "FAIL: no warning for the server that is down"; exit 1; }
rows+=("| http server killed before B's pack, with B's empty --cache-dir | $ms ms | $(share "$ms" "$plain_ms") |")
pack "$work/elsewhere/b" "$work/dead.spk" --remote-cache "http://127.0.0.1:$port/cache"
same "$work/dead.spk"
rows+=("| http server killed before B's pack, no --cache-dir | $ms ms | $(share "$ms" "$plain_ms") |")

# Two shards on two processes, then the assembly.
shard_out=()
start=$(date +%s%N)
for k in 1 2; do
  (cd "$work/a" && "$statepack" pack -i project.json --vulkan --shard "$k/2" --cache-dir "$work/shard-$k" \
    --remote-cache "file:$work/shared") > "$work/shard-$k.txt" 2>&1 &
  shard_out+=($!)
done
for p in "${shard_out[@]}"; do wait "$p"; done
shards_ms=$((($(date +%s%N) - start) / 1000000))
pack "$work/elsewhere/b" "$work/assembled.spk" --no-compile --remote-cache "file:$work/shared"
same "$work/assembled.spk"
for k in 1 2; do
  compiled=$(sed -n 's/.*(\([0-9]*\) compiled.*/\1/p' "$work/shard-$k.txt")
  rows+=("| shard $k/2 compiled | $compiled of $count shaders | $(share "$compiled" "$count") |")
done
rows+=("| both shards, two processes at once | $shards_ms ms | $(share "$shards_ms" "$plain_ms") |")
rows+=("| --no-compile assembly from the shared directory (0 compiles) | $ms ms | $(share "$ms" "$plain_ms") |")

echo
echo "Shared compile cache, $count $kind shaders; without any cache: $plain_ms ms ($(nproc) cores)"
echo
echo "| pack | time | share |"
echo "|---|---|---|"
printf '%s\n' "${rows[@]}"
