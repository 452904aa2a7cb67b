#!/usr/bin/env python3
"""Load on the grammar repository's procedural rule queries (POST /api/v1/queries), on loopback.

Starts `shapegram serve` (release build) on a fresh database, publishes 500 generated goal
grammars of 20 rules each (10,000 rules, over 400 goals, 60 tags and 40 attributes drawn with a
skew, so that some goals are common and most are rare; a tenth of them friends-only or private,
so that visibility does work in every query), then drives the query endpoint with wrk (Debian's
package) for a while and prints requests per second, latency percentiles and errors. Each
request holds `--batch` queries (1 by default: the issue's figure), drawn like the shapes of a
derivation: the keys of a published rule plus a few more, or keys nobody has.

Not part of CI: run by hand and report the figures in docs/repository.md.

    apt-get install wrk
    python3 bench/repository_load.py                       # SQLite in a temporary folder
    python3 bench/repository_load.py --database postgres://user:pw@127.0.0.1/bench
    python3 bench/repository_load.py --batch 50 --seconds 20 --connections 16
"""

import argparse
import json
import os
import random
import re
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")

GRAMMARS = 500
RULES = 20
GOALS = [f"goal{i}" for i in range(400)]
TAGS = [f"tag{i}" for i in range(60)]
ATTRIBUTES = [f"Attr.n{i}" for i in range(40)]


def skewed(rng, names):
    """A name, the first ones far more often than the last (a power law, as real vocabularies)."""
    return names[min(int(len(names) * rng.random() ** 2), len(names) - 1)]


def grammar_text(rng):
    """A goal grammar of RULES rules: goals, tags, attributes, some negations and conditions.
    Returns the text and the positive key sets of its rules."""
    lines, keys = [], []
    for _ in range(RULES):
        goals = sorted({skewed(rng, GOALS) for _ in range(rng.choice([1, 1, 2]))})
        predicates = [f"fulfills({', '.join(goals)})"]
        rule_keys = {f"g:{g}" for g in goals}
        if rng.random() < 0.5:
            tag = skewed(rng, TAGS)
            predicates.append(f"is({tag})")
            rule_keys.add(f"t:{tag}")
        if rng.random() < 0.3:
            attribute = skewed(rng, ATTRIBUTES)
            predicates.append(f"has({attribute})")
            rule_keys.add(f"a:{attribute}")
        if rng.random() < 0.2:
            predicates.append(f"!is({skewed(rng, TAGS)})")
        if rng.random() < 0.1:
            predicates.append("if(scope.sx > 1)")
        colour = "#%06x" % rng.randrange(1 << 24)
        lines.append(f"{' '.join(predicates)} --> color(\"{colour}\")")
        keys.append(rule_keys)
    return "\n".join(lines) + "\n", keys


def call(base, method, path, body=None, token=None):
    data = None if body is None else json.dumps(body).encode()
    request = urllib.request.Request(base + path, data=data, method=method)
    request.add_header("content-type", "application/json")
    if token:
        request.add_header("authorization", f"Bearer {token}")
    try:
        with urllib.request.urlopen(request) as answer:
            return answer.status, json.loads(answer.read() or b"null")
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read() or b"null")


def account(base, name):
    credentials = {"name": name, "password": f"{name} bench password"}
    call(base, "POST", "/api/v1/accounts", credentials)
    status, answer = call(base, "POST", "/api/v1/login", credentials)
    assert status == 200, answer
    return answer["token"]


def populate(base, rng):
    ana, bob = account(base, "ana"), account(base, "bob")
    all_keys = []
    started = time.time()
    for k in range(GRAMMARS):
        text, keys = grammar_text(rng)
        owner, token, visibility = ("ana", ana, "public")
        if k % 10 == 9:
            owner, token = "bob", bob
            visibility = "friends" if k % 20 == 9 else "private"
        status, answer = call(base, "POST", f"/api/v1/grammars/{owner}/g{k}/versions",
                              {"text": text, "visibility": visibility}, token)
        assert status == 201, (status, answer, text)
        if visibility == "public":
            all_keys.extend(keys)
    print(f"published {GRAMMARS} grammars of {RULES} rules in {time.time() - started:.1f} s",
          file=sys.stderr)
    return all_keys


def query(rng, keys):
    """A shape's query: a published rule's keys and one or two more (most), or keys nobody has."""
    if rng.random() < 0.2:
        return {"goals": [f"nobody{rng.randrange(10**6)}"], "tags": [], "attributes": []}
    chosen = set(rng.choice(keys))
    chosen.add(f"g:{rng.choice(GOALS)}")
    if rng.random() < 0.5:
        chosen.add(f"t:{rng.choice(TAGS)}")
    by = {"g": [], "t": [], "a": []}
    for key in chosen:
        prefix, name = key.split(":", 1)
        by[prefix].append(name)
    return {"goals": sorted(by["g"]), "tags": sorted(by["t"]), "attributes": sorted(by["a"])}


def lua_script(bodies, path):
    with open(path, "w") as f:
        f.write("local bodies = {\n")
        for body in bodies:
            # A JSON string is a Lua string literal too (ASCII, the same escapes).
            f.write("  %s,\n" % json.dumps(json.dumps(body)))
        f.write("}\nlocal i = 0\n")
        f.write('wrk.method = "POST"\nwrk.headers["content-type"] = "application/json"\n')
        f.write("request = function()\n  i = i % #bodies + 1\n"
                '  return wrk.format(nil, "/api/v1/queries", nil, bodies[i])\nend\n')


def parse_wrk(text):
    def latency(label):
        m = re.search(rf"^\s*{label}%\s+([\d.]+)(us|ms|s)\s*$", text, re.M)
        if not m:
            return None
        value, unit = float(m.group(1)), m.group(2)
        return value * {"us": 1e-3, "ms": 1.0, "s": 1e3}[unit]
    rps = float(re.search(r"Requests/sec:\s+([\d.]+)", text).group(1))
    non_2xx = re.search(r"Non-2xx or 3xx responses:\s+(\d+)", text)
    socket = re.search(r"Socket errors: connect (\d+), read (\d+), write (\d+), timeout (\d+)",
                       text)
    errors = (int(non_2xx.group(1)) if non_2xx else 0) + (
        sum(int(x) for x in socket.groups()) if socket else 0)
    return {"rps": rps, "p50": latency("50"), "p90": latency("90"), "p99": latency("99"),
            "errors": errors}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--database", help="a postgres:// URL (default: SQLite in a temp folder)")
    parser.add_argument("--batch", type=int, default=1, help="queries per request")
    parser.add_argument("--seconds", type=int, default=30)
    parser.add_argument("--connections", type=int, default=32)
    parser.add_argument("--threads", type=int, default=2, help="wrk's threads")
    parser.add_argument("--bin", help="a shapegram binary (default: a release build)")
    parser.add_argument("--rate-limit", default="1000000/min",
                        help="the server's --rate-limit: counted (the cost is part of every "
                        "request) but never reached by default; `off` to measure without")
    args = parser.parse_args()

    binary = args.bin
    if binary is None:
        subprocess.run(["cargo", "build", "-q", "--release", "-p", "shapegram"], cwd=ROOT,
                       check=True)
        binary = os.path.join(ROOT, "target", "release", "shapegram")
    folder = tempfile.mkdtemp(prefix="shapegram-load-")
    database = ["--database", args.database] if args.database else [
        "--data", os.path.join(folder, "repo.db")]
    server = subprocess.Popen([binary, "serve", "--listen", "127.0.0.1:0", *database,
                               "--rate-limit", args.rate_limit,
                               "--sign-in-rate-limit", "off"],
                              stdout=subprocess.PIPE, text=True)
    try:
        line = server.stdout.readline()
        base = "http://" + re.search(r"http://(\S+)", line).group(1)
        rng = random.Random(17)
        keys = populate(base, rng)
        bodies = [{"queries": [query(rng, keys) for _ in range(args.batch)]}
                  for _ in range(2000)]
        # What the queries find, from the server itself: rules per query, on a sample.
        found = []
        for body in bodies[:200]:
            status, answer = call(base, "POST", "/api/v1/queries", body)
            assert status == 200, answer
            found.extend(sum(len(m["rules"]) for m in a) for a in answer["answers"])
        hits = sum(1 for n in found if n) / len(found)
        print(f"sample: {hits:.0%} of queries find rules, {sum(found) / len(found):.1f} rules "
              f"a query on average, at most {max(found)}", file=sys.stderr)
        script = os.path.join(folder, "queries.lua")
        lua_script(bodies, script)
        wrk = subprocess.run(["wrk", f"-t{args.threads}", f"-c{args.connections}",
                              f"-d{args.seconds}s", "--latency", "-s", script, base],
                             check=True, capture_output=True, text=True)
        print(wrk.stdout, wrk.stderr, file=sys.stderr)
        result = parse_wrk(wrk.stdout)
        backend = "postgresql" if args.database else "sqlite"
        print(f"{backend} (rate limit {args.rate_limit}): {GRAMMARS * RULES} rules in "
              f"{GRAMMARS} grammars, {args.batch} "
              f"quer{'y' if args.batch == 1 else 'ies'} a request, {args.connections} "
              f"connections: {result['rps']:.0f} requests/s, p50 {result['p50']:.1f} ms, "
              f"p90 {result['p90']:.1f} ms, p99 {result['p99']:.1f} ms, {result['errors']} errors")
    finally:
        server.terminate()
        server.wait()


if __name__ == "__main__":
    main()
