#!/usr/bin/python3
# deploy/k8s/check_manifests.py FILE...: offline schema check of Kubernetes
# manifests against the typed models of the Python client
# (python3-kubernetes 22.6 = API 1.22): every field must map to a model
# attribute (a round trip that drops nothing) and the required ones must be
# set (the models' constructors raise on None). Needs Debian's
# python3-kubernetes and python3-yaml (/usr/bin/python3); no cluster, no
# network (kubectl --dry-run=client still asks an API server).
import sys, yaml, json
from kubernetes import client
api = client.ApiClient()
KINDS = {('v1', 'Namespace'): 'V1Namespace', ('v1', 'Service'): 'V1Service',
         ('apps/v1', 'StatefulSet'): 'V1StatefulSet', ('apps/v1', 'Deployment'): 'V1Deployment',
         ('policy/v1', 'PodDisruptionBudget'): 'V1PodDisruptionBudget'}
def norm(x):
    # the models serialise quantities and int-or-string as they came; compare as JSON
    return json.loads(json.dumps(x, sort_keys=True))
def diff(a, b, path=''):
    out = []
    if isinstance(a, dict):
        for k in a:
            if not isinstance(b, dict) or k not in b: out.append(path + '/' + k)
            else: out += diff(a[k], b[k], path + '/' + k)
    elif isinstance(a, list):
        for i, (x, y) in enumerate(zip(a, b)): out += diff(x, y, f'{path}[{i}]')
    elif a != b and str(a) != str(b): out.append(f'{path}: {a!r} -> {b!r}')
    return out
bad = 0
for f in sys.argv[1:]:
    for d in yaml.safe_load_all(open(f)):
        if not d or d['kind'] == 'Kustomization': continue
        model = KINDS[(d['apiVersion'], d['kind'])]
        obj = api._ApiClient__deserialize(d, model)
        back = norm(api.sanitize_for_serialization(obj))
        lost = diff(norm(d), back)
        print(f"{f}: {d['kind']} {d['metadata']['name']}: " + ('ok' if not lost else 'LOST ' + ', '.join(lost)))
        bad += bool(lost)
sys.exit(1 if bad else 0)
