"""A REST client (standard library only): submit a job, follow its progress, read the CSV.

Start the service first (`make run`, or `insect-gait api`), then:

    python examples/05_rest_client.py --url http://127.0.0.1:8000 --duration-s 2
"""

import argparse
import json
import time
import urllib.error
import urllib.request

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--url", default="http://127.0.0.1:8000")
parser.add_argument("--duration-s", type=float, default=2.0)
args = parser.parse_args()


def call(method: str, path: str, body: dict | None = None) -> bytes:
    data = None if body is None else json.dumps(body).encode()
    headers = {"Content-Type": "application/json"}
    try:
        req = urllib.request.Request(args.url + path, data, headers, method=method)
        with urllib.request.urlopen(req, timeout=30) as resp:
            return resp.read()
    except urllib.error.HTTPError as exc:  # the service refused: its reason, in one line
        raise SystemExit(f"{method} {path}: {exc.code} {exc.read().decode()[:300]}") from None
    except (OSError, ValueError) as exc:  # nothing listens there, or no URL at all
        why = getattr(exc, "reason", exc)
        raise SystemExit(f"no insect-gait API at {args.url} ({why}): start it with `make run` "
                         "or `insect-gait api`, or pass --url") from None  # fmt: skip


spec = {"kind": "run", "beta": 0.66, "d31_init": [2.0, 3.0], "duration_s": args.duration_s}
job = json.loads(call("POST", "/v1/jobs", spec))
print(f"queued job {job['id']}")
while job["status"] in ("queued", "running"):
    time.sleep(0.5)
    job = json.loads(call("GET", f"/v1/jobs/{job['id']}"))
    print(f"  {job['status']} {job['progress']:.0%}")
if job["status"] != "done":
    raise SystemExit(f"job {job['status']}: {job.get('error')}")
print(call("GET", f"/v1/jobs/{job['id']}/result?format=csv").decode())
