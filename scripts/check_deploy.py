#!/usr/bin/env python3
"""Checks the deploy files by parsing them, since no cluster runs in CI.

Debian 12 packages no Kubernetes schema validator (no kubeconform or kubeval), so this
checks what a schema would and more that one could not: every YAML file parses (duplicate
keys refused), every Kubernetes object has apiVersion, kind and metadata.name with the
apiVersion its kind takes, workloads have images, resources and probes (native gRPC ones
for isocorr-server on its --listen port), the flags given to isocorr-server exist in its
--help, and names that refer to each other (Secrets, Services, selectors, the Envoy
cluster, kustomization files) agree.

usage: check_deploy.py REPO_DIR SERVER_HELP_FILE   (prints every problem; exit 1 if any)
       check_deploy.py --self-test REPO_DIR SERVER_HELP_FILE
"""
import copy
import os
import re
import sys

import yaml

# The apiVersion each kind the manifests use takes today.
API_VERSIONS = {
    "Deployment": "apps/v1",
    "StatefulSet": "apps/v1",
    "Service": "v1",
    "Secret": "v1",
    "ConfigMap": "v1",
    "PodDisruptionBudget": "policy/v1",
    "HorizontalPodAutoscaler": "autoscaling/v2",
}
WORKLOAD_KINDS = ("Deployment", "StatefulSet")
SERVER_IMAGE = "isocorr:"


class UniqueKeyLoader(yaml.SafeLoader):
    """SafeLoader that refuses a key given twice in one mapping (PyYAML keeps the last)."""


def _construct_unique_mapping(loader, node, deep=False):
    seen = set()
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=deep)
        if key in seen:
            raise yaml.constructor.ConstructorError(
                None, None, "duplicate key %r" % (key,), key_node.start_mark)
        seen.add(key)
    return loader.construct_mapping(node, deep)


UniqueKeyLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_unique_mapping)


def load_all(path):
    with open(path) as f:
        return [doc for doc in yaml.load_all(f, Loader=UniqueKeyLoader) if doc is not None]


def server_flags(help_text):
    return set(re.findall(r"--[a-z][a-z0-9-]*", help_text))


def flags_in(args):
    return [a.split("=", 1)[0] for a in args if isinstance(a, str) and a.startswith("--")]


def flag_value(args, flag):
    for i, a in enumerate(args):
        if a == flag and i + 1 < len(args):
            return args[i + 1]
        if isinstance(a, str) and a.startswith(flag + "="):
            return a.split("=", 1)[1]
    return None


def listen_port(args):
    listen = flag_value(args, "--listen")
    return int(listen.rsplit(":", 1)[1]) if listen and ":" in listen else None


def selects(selector, labels):
    return bool(selector) and all(labels.get(k) == v for k, v in selector.items())


class Checker:
    def __init__(self, help_text):
        self.flags = server_flags(help_text)
        self.problems = []

    def problem(self, where, what):
        self.problems.append("%s: %s" % (where, what))

    # --- Kubernetes ---------------------------------------------------------------------

    def check_k8s(self, docs_by_file, kustomization, envoy):
        objects = []
        for path, docs in docs_by_file.items():
            for doc in docs:
                if not isinstance(doc, dict):
                    self.problem(path, "a document that is not a mapping")
                    continue
                kind, name = doc.get("kind"), (doc.get("metadata") or {}).get("name")
                where = "%s: %s/%s" % (path, kind, name)
                if not doc.get("apiVersion") or not kind or not name:
                    self.problem(where, "apiVersion, kind and metadata.name are required")
                    continue
                if API_VERSIONS.get(kind) != doc["apiVersion"]:
                    self.problem(where, "kind %s takes apiVersion %s, not %s"
                                 % (kind, API_VERSIONS.get(kind, "(unknown kind)"), doc["apiVersion"]))
                objects.append((where, doc))
        generated = {g.get("name") for g in kustomization.get("configMapGenerator", [])}
        secrets = {d["metadata"]["name"]: set((d.get("stringData") or {}).keys()) | set((d.get("data") or {}).keys())
                   for _, d in objects if d["kind"] == "Secret"}
        pods = {}  # workload name -> pod labels
        for where, doc in objects:
            if doc["kind"] in WORKLOAD_KINDS:
                pods[doc["metadata"]["name"]] = self.check_workload(where, doc, secrets, generated)
        for where, doc in objects:
            spec = doc.get("spec") or {}
            if doc["kind"] == "Service":
                if not spec.get("ports"):
                    self.problem(where, "a Service needs ports")
                if not any(selects(spec.get("selector"), labels) for labels in pods.values()):
                    self.problem(where, "its selector matches no workload's pods")
            elif doc["kind"] == "PodDisruptionBudget":
                if "minAvailable" not in spec and "maxUnavailable" not in spec:
                    self.problem(where, "needs minAvailable or maxUnavailable")
                selector = (spec.get("selector") or {}).get("matchLabels")
                if not any(selects(selector, labels) for labels in pods.values()):
                    self.problem(where, "its selector matches no workload's pods")
            elif doc["kind"] == "HorizontalPodAutoscaler":
                target = spec.get("scaleTargetRef") or {}
                if target.get("name") not in pods or not spec.get("metrics") or not spec.get("maxReplicas"):
                    self.problem(where, "needs scaleTargetRef naming a workload here, metrics and maxReplicas")
        service_names = {d["metadata"]["name"] for _, d in objects if d["kind"] == "Service"}
        self.check_envoy_target("deploy/k8s", envoy, service_names)

    def check_workload(self, where, doc, secrets, generated):
        spec = doc.get("spec") or {}
        template = spec.get("template") or {}
        labels = (template.get("metadata") or {}).get("labels") or {}
        if not selects((spec.get("selector") or {}).get("matchLabels"), labels):
            self.problem(where, "spec.selector.matchLabels must match the pod template's labels")
        pod = template.get("spec") or {}
        volumes = {v.get("name"): v for v in pod.get("volumes") or []}
        volumes.update({(c.get("metadata") or {}).get("name"): {} for c in spec.get("volumeClaimTemplates") or []})
        for volume in volumes.values():
            secret = (volume.get("secret") or {}).get("secretName")
            if secret and secret not in secrets:
                self.problem(where, "volume from Secret %s, which no manifest defines" % secret)
            config_map = (volume.get("configMap") or {}).get("name")
            if config_map and config_map not in generated:
                self.problem(where, "volume from ConfigMap %s, which kustomization.yaml does not generate" % config_map)
        containers = pod.get("containers") or []
        if not containers:
            self.problem(where, "no containers")
        for container in containers:
            self.check_container("%s container %s" % (where, container.get("name")), container, secrets, volumes)
        return labels

    def check_container(self, where, container, secrets, volumes):
        if not container.get("image"):
            self.problem(where, "no image")
        resources = container.get("resources") or {}
        if not (resources.get("requests") or {}).get("memory") or not (resources.get("limits") or {}).get("memory"):
            self.problem(where, "needs resources.requests.memory and resources.limits.memory")
        for probe in ("readinessProbe", "livenessProbe"):
            if not container.get(probe):
                self.problem(where, "no %s" % probe)
        env = {}
        for e in container.get("env") or []:
            env[e.get("name")] = e
            ref = (e.get("valueFrom") or {}).get("secretKeyRef")
            if ref and ref.get("key") not in secrets.get(ref.get("name"), set()):
                self.problem(where, "env %s from Secret %s key %s, which is not defined"
                             % (e.get("name"), ref.get("name"), ref.get("key")))
        args = [str(a) for a in (container.get("command") or []) + (container.get("args") or [])]
        for var in re.findall(r"\$\(([A-Za-z_][A-Za-z0-9_]*)\)", " ".join(args)):
            if var not in env:
                self.problem(where, "$(%s) in args, but no env %s" % (var, var))
        mounts = [m.get("mountPath", "") for m in container.get("volumeMounts") or []]
        for m in container.get("volumeMounts") or []:
            if m.get("name") not in volumes:
                self.problem(where, "mounts volume %s, which the pod does not declare" % m.get("name"))
        if container.get("image", "").startswith(SERVER_IMAGE):
            self.check_server_args(where, args)
            port = listen_port(args)
            for probe in ("startupProbe", "readinessProbe", "livenessProbe"):
                grpc = (container.get(probe) or {}).get("grpc")
                if not grpc or grpc.get("port") != port:
                    self.problem(where, "%s must be a native grpc probe on the --listen port %s" % (probe, port))
            for flag in ("--token-file",):
                path = flag_value(args, flag)
                if path and not any(path.startswith(m.rstrip("/") + "/") for m in mounts):
                    self.problem(where, "%s %s lies in no mounted volume" % (flag, path))

    def check_server_args(self, where, args):
        for flag in flags_in(args):
            if flag not in self.flags:
                self.problem(where, "isocorr-server has no flag %s (see isocorr-server --help)" % flag)
        if listen_port(args) is None:
            self.problem(where, "isocorr-server needs --listen HOST:PORT")

    def check_envoy_target(self, where, envoy, names):
        for address, port in envoy_targets(envoy):
            if address not in names:
                self.problem(where, "Envoy sends calls to %s, which is not defined here" % address)

    # --- kustomization, Envoy, compose, Dockerfile --------------------------------------

    def check_kustomization(self, k8s_dir, kustomization):
        for resource in kustomization.get("resources") or []:
            if not os.path.isfile(os.path.join(k8s_dir, resource)):
                self.problem("deploy/k8s/kustomization.yaml", "resource %s does not exist" % resource)
        for generator in kustomization.get("configMapGenerator") or []:
            for entry in generator.get("files") or []:
                if not os.path.isfile(os.path.join(k8s_dir, entry.split("=", 1)[-1])):
                    self.problem("deploy/k8s/kustomization.yaml", "configMapGenerator file %s does not exist" % entry)

    def check_envoy(self, envoy, server_port):
        where = "deploy/k8s/envoy/envoy.yaml"
        clusters = (envoy.get("static_resources") or {}).get("clusters") or []
        for cluster in clusters:
            if cluster.get("lb_policy") not in ("RING_HASH", "MAGLEV"):
                self.problem(where, "cluster %s: consistent hashing needs lb_policy RING_HASH or MAGLEV"
                             % cluster.get("name"))
        if not any(p.get("header", {}).get("header_name") for p in iter_key(envoy, "hash_policy")):
            self.problem(where, "no route hashes on a header (the mesh digest)")
        for address, port in envoy_targets(envoy):
            if port != server_port:
                self.problem(where, "sends calls to port %s, but the servers listen on %s" % (port, server_port))
        if not clusters:
            self.problem(where, "no clusters")

    def check_compose(self, compose, envoy):
        where = "deploy/compose.yaml"
        services = compose.get("services") or {}
        if not services:
            self.problem(where, "no services")
        aliases = set(services)
        for name, service in services.items():
            if not service.get("image") and not service.get("build"):
                self.problem(where, "service %s needs an image or a build" % name)
            for dependency in service.get("depends_on") or []:
                if dependency not in services:
                    self.problem(where, "service %s depends on %s, which is not defined" % (name, dependency))
            for network in (service.get("networks") or {}).values():
                aliases.update((network or {}).get("aliases") or [])
            for volume in service.get("volumes") or []:
                source = volume.split(":", 1)[0]
                if not source.startswith((".", "/")) and source not in (compose.get("volumes") or {}):
                    self.problem(where, "service %s uses volume %s, which is not declared" % (name, source))
        servers = [s for s in services.values() if str(s.get("image", "")).startswith(SERVER_IMAGE)]
        if len(servers) != 1 or ((servers[0].get("deploy") or {}).get("replicas") or 1) < 2:
            self.problem(where, "one isocorr service with deploy.replicas >= 2 expected")
        for server in servers:
            args = [str(a) for a in server.get("command") or []]
            self.check_server_args("%s isocorr" % where, args)
            if "--store" not in args:
                self.problem(where, "the replicas need the shared --store")
        self.check_envoy_target(where, envoy, aliases)
        return servers

    def check_dockerfile(self, path):
        text = open(path).read()
        for line in re.findall(r"^(?:CMD|ENTRYPOINT)\s+(\[.*\])\s*$", text, re.M):
            args = yaml.safe_load(line)
            if args and args[0].startswith("--"):
                self.check_server_args("Dockerfile CMD", args)


def iter_key(node, key):
    if isinstance(node, dict):
        for k, v in node.items():
            if k == key:
                yield from (v if isinstance(v, list) else [v])
            else:
                yield from iter_key(v, key)
    elif isinstance(node, list):
        for item in node:
            yield from iter_key(item, key)


def envoy_targets(envoy):
    for address in iter_key(envoy, "socket_address"):
        if address.get("address") not in ("0.0.0.0", "::"):
            yield address.get("address"), address.get("port_value")


def load_deploy(repo):
    deploy = os.path.join(repo, "deploy")
    k8s = os.path.join(deploy, "k8s")
    files = {}
    for name in sorted(os.listdir(k8s)):
        if name.endswith((".yaml", ".yml")):
            files[name] = load_all(os.path.join(k8s, name))
    kustomization = files.pop("kustomization.yaml")[0]
    envoy = load_all(os.path.join(k8s, "envoy", "envoy.yaml"))[0]
    compose = load_all(os.path.join(deploy, "compose.yaml"))[0]
    return k8s, files, kustomization, envoy, compose


def check(repo, help_text, loaded=None):
    checker = Checker(help_text)
    try:
        k8s, files, kustomization, envoy, compose = loaded or load_deploy(repo)
    except (yaml.YAMLError, OSError, KeyError, IndexError) as e:
        checker.problem("deploy", "cannot load: %s" % e)
        return checker.problems
    checker.check_kustomization(k8s, kustomization)
    checker.check_k8s(files, kustomization, envoy)
    servers = checker.check_compose(compose, envoy)
    server_ports = {listen_port([str(a) for a in s.get("command") or []]) for s in servers}
    checker.check_envoy(envoy, server_ports.pop() if len(server_ports) == 1 else None)
    checker.check_dockerfile(os.path.join(repo, "Dockerfile"))
    return checker.problems


def server_container(files):
    for doc in files["isocorr-server.yaml"]:
        if doc["kind"] == "Deployment":
            return doc["spec"]["template"]["spec"]["containers"][0]
    raise KeyError("no isocorr-server Deployment")


def self_test(repo, help_text):
    """Each broken copy of the real files must be reported: the checks can fail."""
    loaded = load_deploy(repo)

    def broken(change):
        copied = copy.deepcopy(loaded)
        change(*copied)
        return check(repo, help_text, copied)

    cases = {
        "a probe removed": lambda k8s, f, k, e, c: server_container(f).pop("livenessProbe"),
        "an HTTP probe": lambda k8s, f, k, e, c: server_container(f).update(readinessProbe={"httpGet": {"port": 80}}),
        "an unknown flag": lambda k8s, f, k, e, c: server_container(f)["args"].append("--no-such-flag"),
        "a missing name": lambda k8s, f, k, e, c: f["pdb.yaml"][0]["metadata"].pop("name"),
        "a wrong apiVersion": lambda k8s, f, k, e, c: f["pdb.yaml"][0].update(apiVersion="policy/v1beta1"),
        "an unknown Secret key": lambda k8s, f, k, e, c: server_container(f)["env"][1]["valueFrom"]["secretKeyRef"]
        .update(key="nope"),
        "no memory limit": lambda k8s, f, k, e, c: server_container(f)["resources"].pop("limits"),
        "one compose replica": lambda k8s, f, k, e, c: c["services"]["isocorr"]["deploy"].update(replicas=1),
        "round robin in Envoy": lambda k8s, f, k, e, c: e["static_resources"]["clusters"][0]
        .update(lb_policy="ROUND_ROBIN"),
        "Envoy to another name": lambda k8s, f, k, e, c: e["static_resources"]["clusters"][0]["load_assignment"]
        ["endpoints"][0]["lb_endpoints"][0]["endpoint"]["address"]["socket_address"].update(address="elsewhere"),
    }
    failed = [name for name, change in cases.items() if not broken(change)]
    duplicate = "a: 1\na: 2\n"
    try:
        yaml.load(duplicate, Loader=UniqueKeyLoader)
        failed.append("a duplicate key")
    except yaml.YAMLError:
        pass
    for name in failed:
        print("check-deploy self-test: %s was not reported" % name)
    return not failed


def main(argv):
    testing = argv[1:2] == ["--self-test"]
    if testing:
        argv = argv[:1] + argv[2:]
    if len(argv) != 3:
        print(__doc__.strip().split("\n\n")[-1])
        return 2
    repo, help_text = argv[1], open(argv[2]).read()
    if "--listen" not in server_flags(help_text):
        print("check-deploy: %s is not isocorr-server --help output" % argv[2])
        return 2
    if testing:
        return 0 if self_test(repo, help_text) else 1
    problems = check(repo, help_text)
    for p in problems:
        print("check-deploy: " + p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
