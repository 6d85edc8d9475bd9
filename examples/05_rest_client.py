"""A REST client (standard library only): submit a job, follow its progress, read the CSV.

Start the service first (`make run`, or `insect-gait api`), then:

    python examples/05_rest_client.py --url http://127.0.0.1:8000 --duration-s 2
"""

import argparse
import json
import time
import urllib.request

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--url", default="http://127.0.0.1:8000")
parser.add_argument("--duration-s", type=float, default=2.0)
args = parser.parse_args()


def call(method: str, path: str, body: dict | None = None) -> bytes:
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(
        args.url + path, data=data, method=method, headers={"Content-Type": "application/json"}
    )
    with urllib.request.urlopen(req, timeout=30) as resp:
        return resp.read()


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
