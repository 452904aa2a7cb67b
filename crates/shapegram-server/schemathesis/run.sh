#!/bin/sh
# Property-based tests of `shapegram serve` against its own OpenAPI document with Schemathesis
# (not in CI: too heavy). Starts a server on a fresh database, signs up ana, bo and cy, publishes
# ana/wood and ana/spare, has ana ask bo and cy ask ana to be friends, then runs every check of
# Schemathesis: anonymously, with ana's token, with ana's token and the grammar and friend routes
# pinned to what exists (seeded.toml), and token revocation with bo's token (apart, since
# revoking ana's would end her runs).
#
#   python3 -m venv /tmp/st && /tmp/st/bin/pip install schemathesis
#   cargo build -p shapegram
#   ST=/tmp/st/bin/schemathesis crates/shapegram-server/schemathesis/run.sh [EXAMPLES] [SEED]
#
# SHAPEGRAM (default target/debug/shapegram) names the executable. Exits non-zero when a run
# fails; the reports are in $OUT (default a new directory under /tmp).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
st=${ST:-schemathesis}
case $st in */*) st=$(realpath "$st") ;; esac
shapegram=${SHAPEGRAM:-target/debug/shapegram}
examples=${1:-100}
seed=${2:-1}
out=${OUT:-$(mktemp -d /tmp/shapegram-schemathesis.XXXXXX)}

"$shapegram" serve --data "$out/repo.db" --listen 127.0.0.1:0 --rate-limit off \
    --sign-in-rate-limit off >"$out/server.out" 2>"$out/server.err" &
server=$!
trap 'kill $server' EXIT
addr=
for _ in $(seq 100); do
    addr=$(grep -ho '127\.0\.0\.1:[0-9]*' "$out/server.out" "$out/server.err" | head -n 1) || true
    [ -n "$addr" ] && break
    sleep 0.1
done
[ -n "$addr" ] || { cat "$out/server.err"; exit 1; }
base=http://$addr

post() { # PATH BODY [TOKEN]
    curl -sf -X POST "$base$1" -H 'content-type: application/json' \
        ${3:+-H "authorization: Bearer $3"} -d "$2"
}
post /api/v1/accounts '{"name": "ana", "password": "correct horse"}' >/dev/null
post /api/v1/accounts '{"name": "bo", "password": "correct horse"}' >/dev/null
post /api/v1/accounts '{"name": "cy", "password": "correct horse"}' >/dev/null
token=$(post /api/v1/login '{"name": "ana", "password": "correct horse"}' |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["token"])')
post /api/v1/grammars/ana/wood/versions \
    '{"text": "axiom wooden size(1, 1, 1)\nfulfills(wooden) --> color(\"#8b5a2b\")\n"}' \
    "$token" >/dev/null
post /api/v1/grammars/ana/spare/versions '{"text": "fulfills(spare) --> color(1)\n"}' "$token" \
    >/dev/null
post /api/v1/friends/bo '' "$token" >/dev/null
bo_token=$(post /api/v1/login '{"name": "bo", "password": "correct horse"}' |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["token"])')
cy_token=$(post /api/v1/login '{"name": "cy", "password": "correct horse"}' |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["token"])')
post /api/v1/friends/ana '' "$cy_token" >/dev/null

status=0
run() { # NAME CONFIG [ARGS...]
    name=$1 config=$2
    shift 2
    echo "== $name"
    # In $out, where Hypothesis keeps its example database.
    (cd "$out" && "$st" --config-file "$here/$config" run "$base/openapi.json" --checks all \
        --max-examples "$examples" --seed "$seed" --workers 2 --no-color \
        --report junit --report-dir "$out/$name" "$@") >"$out/$name.txt" 2>&1 || status=1
    sed -n '/^Failures:/,/^$/p; /^Test cases:/,$p' "$out/$name.txt"
}
run anonymous schemathesis.toml
# Revoking the run's own token would leave the rest of the run anonymous.
run token schemathesis.toml -H "Authorization: Bearer $token" \
    --exclude-path '/api/v1/tokens/{id}'
run seeded seeded.toml -H "Authorization: Bearer $token" --exclude-path '/api/v1/tokens/{id}'
run revoke schemathesis.toml -H "Authorization: Bearer $bo_token" --include-path '/api/v1/tokens/{id}'
echo "reports in $out"
exit $status
