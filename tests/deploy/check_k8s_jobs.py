#!/usr/bin/python3
"""The Kubernetes Job manifests in deploy/ against the batch/v1 Job schema (not run on a cluster).

    /usr/bin/python3 tests/deploy/check_k8s_jobs.py deploy/plan-job.yaml deploy/plan-merge-job.yaml

The schema is the one Debian's python3-kubernetes (22.6, Kubernetes 1.22's API) was generated
from: every model's `openapi_types` (field → type) and `attribute_map` (field → JSON key). Checked:
  * every key is a field of its object (a misspelt key, which the API server would drop or refuse,
    is named with its path), every value has the field's type (object, list, map, string, integer,
    boolean), recursively from V1Job;
  * the required fields are there: the client's own models are built from the document with its
    client-side validation (V1Container.name, V1PodSpec.containers, V1JobSpec.template, ...);
  * what the API server's validation adds for a Job: apiVersion batch/v1, kind Job, a DNS-1123
    name, restartPolicy Never or OnFailure, parallelism <= completions, every volumeMount naming a
    volume, and for completionMode Indexed a completion count;
  * toolpoint's own contract: an Indexed Job's command shards with $JOB_COMPLETION_INDEX/N and N
    equal to `completions`, writing parts/part-$JOB_COMPLETION_INDEX.json; a merge Job merges them.
Before the files, the checker is shown to fail on broken copies of the first one (a misspelt key,
a wrong type, no containers, N not the completion count), so a pass means something.
Exit 0 passed, 1 failed, 77 skipped (python3-kubernetes or python3-yaml missing).
"""
import copy
import re
import sys

try:
    import yaml
    import kubernetes.client as k8s
    from kubernetes.client import ApiClient
except ImportError as e:  # ctest SKIP_RETURN_CODE
    print(f"SKIPPED: {e}: install Debian's python3-kubernetes and python3-yaml (bash scripts/run.sh build does)")
    sys.exit(77)

DNS1123_SUBDOMAIN = re.compile(r"^[a-z0-9]([-a-z0-9]*[a-z0-9])?(\.[a-z0-9]([-a-z0-9]*[a-z0-9])?)*$")
PRIMITIVE = {"str": str, "int": int, "bool": bool, "float": (int, float), "datetime": str, "date": str}


def check_type(value, kind, path, errors):
    """Appends to errors where `value` is not of the schema type `kind` (a model's openapi_types text)."""
    if kind == "object":
        return
    if kind.startswith("list["):
        if not isinstance(value, list):
            errors.append(f"{path}: expected a list, got {type(value).__name__}")
            return
        for i, v in enumerate(value):
            check_type(v, kind[5:-1], f"{path}[{i}]", errors)
        return
    if kind.startswith("dict("):
        if not isinstance(value, dict):
            errors.append(f"{path}: expected a map, got {type(value).__name__}")
            return
        inner = kind[5:-1].split(", ", 1)[1]
        for key, v in value.items():
            check_type(v, inner, f"{path}.{key}", errors)
        return
    if kind in PRIMITIVE:
        ok = isinstance(value, PRIMITIVE[kind]) and not (kind != "bool" and isinstance(value, bool))
        if not ok:
            errors.append(f"{path}: expected {kind}, got {type(value).__name__} {value!r}")
        return
    model = getattr(k8s, kind)
    if not isinstance(value, dict):
        errors.append(f"{path}: expected a {kind} object, got {type(value).__name__}")
        return
    by_key = {json_key: field for field, json_key in model.attribute_map.items()}
    for key, v in value.items():
        if key not in by_key:
            errors.append(f"{path}.{key}: not a field of {kind} (its fields: {', '.join(sorted(by_key))})")
        else:
            check_type(v, model.openapi_types[by_key[key]], f"{path}.{key}", errors)


def check_job(doc, source):
    errors = []
    if not isinstance(doc, dict):
        return [f"{source}: not a YAML object"]
    if doc.get("apiVersion") != "batch/v1" or doc.get("kind") != "Job":
        errors.append(f"{source}: apiVersion/kind {doc.get('apiVersion')}/{doc.get('kind')}, expected batch/v1 Job")
    check_type(doc, "V1Job", source, errors)
    if errors:
        return errors
    try:  # required fields: the client's models refuse None for them
        ApiClient()._ApiClient__deserialize(copy.deepcopy(doc), "V1Job")
    except (ValueError, TypeError) as e:
        errors.append(f"{source}: {e}")
        return errors
    name = doc.get("metadata", {}).get("name", "")
    if not DNS1123_SUBDOMAIN.match(name) or len(name) > 63:
        errors.append(f"{source}: metadata.name {name!r} is not a DNS-1123 name of at most 63 characters")
    spec = doc["spec"]
    pod = spec["template"]["spec"]
    if pod.get("restartPolicy") not in ("Never", "OnFailure"):
        errors.append(f"{source}: a Job's restartPolicy must be Never or OnFailure, not {pod.get('restartPolicy')!r}")
    completions, parallelism = spec.get("completions"), spec.get("parallelism")
    if completions is not None and parallelism is not None and parallelism > completions:
        errors.append(f"{source}: parallelism {parallelism} > completions {completions}")
    volumes = {v["name"] for v in pod.get("volumes", [])}
    for c in pod["containers"]:
        for m in c.get("volumeMounts", []):
            if m["name"] not in volumes:
                errors.append(f"{source}: container {c['name']} mounts volume {m['name']!r}, which the pod does not have")
    command = " ".join(" ".join(c.get("command", []) + c.get("args", [])) for c in pod["containers"])
    if spec.get("completionMode") == "Indexed":
        if completions is None:
            errors.append(f"{source}: an Indexed Job needs spec.completions")
        m = re.search(r"--shard \"?\$\{?JOB_COMPLETION_INDEX\}?/(\d+)", command)
        if not m:
            errors.append(f"{source}: the command does not shard with --shard $JOB_COMPLETION_INDEX/N: {command}")
        elif int(m.group(1)) != completions:
            errors.append(f"{source}: the command splits into {m.group(1)} shards but spec.completions is {completions}")
        if not re.search(r"--part \"?[^ ]*part-\$\{?JOB_COMPLETION_INDEX\}?\.json", command):
            errors.append(f"{source}: the command does not write --part .../part-$JOB_COMPLETION_INDEX.json")
    elif "plan merge" not in command:
        errors.append(f"{source}: neither an Indexed Job with shards nor a merge (`toolpoint plan merge`)")
    return errors


def load(path):
    with open(path) as f:
        return [d for d in yaml.safe_load_all(f) if d is not None]


def main(paths):
    # The checker fails where it should: broken copies of the first manifest.
    job = load(paths[0])[0]
    broken = []
    b = copy.deepcopy(job)
    b["spec"]["template"]["spec"]["containers"][0]["volumeMount"] = b["spec"]["template"]["spec"]["containers"][0].pop(
        "volumeMounts", [])
    broken.append(("a misspelt key", b, "volumeMount: not a field of V1Container"))
    b = copy.deepcopy(job)
    b["spec"]["completions"] = str(b["spec"].get("completions"))
    broken.append(("a string for an integer", b, "spec.completions: expected int"))
    b = copy.deepcopy(job)
    del b["spec"]["template"]["spec"]["containers"]
    broken.append(("no containers", b, "containers"))
    b = copy.deepcopy(job)
    b["spec"]["completions"] = (b["spec"].get("completions") or 1) + 1
    b["spec"]["parallelism"] = 1
    broken.append(("N not the completion count", b, "spec.completions is"))
    failed = False
    for what, doc, expected in broken:
        errors = check_job(doc, "broken")
        if not any(expected in e for e in errors):
            print(f"FAILED: the checker passed {what} (expected an error with {expected!r}; got {errors})")
            failed = True
    for path in paths:
        for i, doc in enumerate(load(path)):
            errors = check_job(doc, f"{path}[{i}]")
            for e in errors:
                print(f"FAILED: {e}")
            failed |= bool(errors)
            if not errors:
                print(f"{path}[{i}]: batch/v1 Job {doc['metadata']['name']}: valid")
    return 1 if failed else 0


if __name__ == "__main__":
    if len(sys.argv) < 2:
        print("usage: check_k8s_jobs.py MANIFEST.yaml...", file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1:]))
