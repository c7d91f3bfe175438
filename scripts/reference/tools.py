"""Shared helpers of the reference-tool scripts: read IDES3 .xmd files, build libFAUDES and TCT models.

Only the Python standard library plus `faudes` (libFAUDES) and `pitct` (TCT), installed in the project's
venv by scripts/setup.sh.
"""
import os
import subprocess
import xml.etree.ElementTree as ET

import faudes
import pitct


class Fsa:
    """A plain automaton: state names and marking, initial index, events with controllability, transitions."""

    def __init__(self, name, states, initial, events, trans):
        self.name = name
        self.states = states  # [(name, marked)]
        self.initial = initial  # index or None
        self.events = events  # {name: controllable}
        self.trans = trans  # [(src index, event name, dst index)]


def read_xmd(path):
    root = ET.parse(path).getroot()
    data = root.find("data")
    ids, states, initial = {}, [], None
    for s in data.findall("state"):
        props = s.find("properties")
        ids[s.get("id")] = len(states)
        if props is not None and props.find("initial") is not None:
            initial = len(states)
        states.append((s.findtext("name"), props is not None and props.find("marked") is not None))
    events, names = {}, {}
    for e in data.findall("event"):
        props = e.find("properties")
        names[e.get("id")] = e.findtext("name")
        events[e.findtext("name")] = props is not None and props.find("controllable") is not None
    trans = [(ids[t.get("source")], names[t.get("event")], ids[t.get("target")]) for t in data.findall("transition")]
    name = os.path.splitext(os.path.basename(path))[0]
    return Fsa(name, states, initial, events, trans)


def read_wmod(path):
    """{kind: [Fsa]} of a Supremica module as the script reads it itself: simple components only, edges
    with one label each or several, `:accepting` marking (a component without it marks every state)."""
    ns = {"m": "http://waters.sourceforge.net/xsd/module"}
    root = ET.parse(path).getroot()
    kinds = {d.get("Name"): d.get("Kind") for d in root.find("m:EventDeclList", ns)}
    out = {}
    for c in root.find("m:ComponentList", ns).findall("m:SimpleComponent", ns):
        graph = c.find("m:Graph", ns)
        nodes = graph.find("m:NodeList", ns).findall("m:SimpleNode", ns)
        accepting = any(i.get("Name") == ":accepting" for n in nodes for i in n.iter(f"{{{ns['m']}}}SimpleIdentifier"))
        ids, states, initial = {}, [], None
        for n in nodes:
            ids[n.get("Name")] = len(states)
            if n.get("Initial") == "true":
                initial = len(states)
            marked = any(i.get("Name") == ":accepting" for i in n.iter(f"{{{ns['m']}}}SimpleIdentifier"))
            states.append((n.get("Name"), marked or not accepting))
        trans, events = [], {}
        for e in graph.find("m:EdgeList", ns).findall("m:Edge", ns):
            for label in e.find("m:LabelBlock", ns).findall("m:SimpleIdentifier", ns):
                name = label.get("Name")
                events[name] = kinds[name] == "CONTROLLABLE"
                trans.append((ids[e.get("Source")], name, ids[e.get("Target")]))
        out.setdefault(c.get("Kind"), []).append(Fsa(c.get("Name"), states, initial, events, trans))
    return out


def read_manifest(path):
    """(plants, specs) of a manifest written by the `families` example (plain lists of relative paths)."""
    import tomllib

    with open(path, "rb") as f:
        m = tomllib.load(f)
    base = os.path.dirname(path)
    return ([read_xmd(os.path.join(base, p)) for p in m.get("plants", [])],
            [read_xmd(os.path.join(base, p)) for p in m.get("specs", [])])


def to_faudes(a):
    g = faudes.System()
    g.Name(a.name)
    for e, c in sorted(a.events.items()):
        g.InsEvent(e)
        if c:
            g.SetControllable(e)
    idx = [g.InsState() for _ in a.states]
    for i, (_, marked) in enumerate(a.states):
        if marked:
            g.SetMarkedState(idx[i])
    if a.initial is not None:
        g.SetInitState(idx[a.initial])
    for s, e, t in a.trans:
        g.SetTransition(idx[s], g.EventIndex(e), idx[t])
    return g


def faudes_product(automata):
    acc = to_faudes(automata[0])
    for a in automata[1:]:
        res = faudes.System()
        faudes.Parallel(acc, to_faudes(a), res)
        acc = res
    return acc


def faudes_supc(plants, specs):
    """supC(G, G || E) with E lifted to the alphabet of G (InvProject)."""
    g = faudes_product(plants)
    e = faudes_product(specs)
    alphabet = faudes.EventSet(g.Alphabet())
    alphabet.InsertSet(e.Alphabet())
    faudes.InvProject(g, alphabet)
    faudes.InvProject(e, alphabet)
    for a in plants + specs:
        for ev, controllable in a.events.items():
            if controllable:
                g.SetControllable(ev)
    sup = faudes.System()
    faudes.SupCon(g, e, sup)
    return sup


def faudes_nonconflicting(automata):
    vec = faudes.GeneratorVector()
    for a in automata:
        vec.Append(to_faudes(a))
    return faudes.IsNonblocking(vec)


class Tct:
    """TCT through pitct: integer events, odd = controllable, even = uncontrollable (TCT's convention).

    A TCT DES has no declared alphabet: an event without transitions is simply absent, and `sync` leaves
    it free. To keep our semantics (an event of the alphabet without a transition is disabled), every
    automaton is lifted to an explicit universe of events with selfloops of the events outside its own
    alphabet, and products are `meet`s of lifted automata.
    """

    def __init__(self, workdir, automata):
        pitct.init(workdir, overwrite=True)
        names = sorted({e: c for a in automata for e, c in a.events.items()}.items())
        self.code = {}
        for i, (e, c) in enumerate(names):
            self.code[e] = 2 * i + 1 if c else 2 * i + 2

    def create(self, name, a, universe=()):
        """Creates `a` as `name`, lifted with selfloops of the events of `universe` it lacks."""
        trans = [(s, self.code[e], t) for s, e, t in a.trans]
        marked = [i for i, (_, m) in enumerate(a.states) if m]
        # TCT's state 0 is initial: swap the initial state with state 0.
        init = a.initial or 0
        swap = lambda x: init if x == 0 else (0 if x == init else x)
        extra = sorted(self.code[e] for e in set(universe) - set(a.events))
        raw = name + "_raw" if extra else name
        pitct.create(raw, max(len(a.states), 1), [(swap(s), e, swap(t)) for s, e, t in trans], [swap(m) for m in marked])
        if extra:
            pitct.selfloop(name, raw, extra)
        return name

    def condat(self, name, plant, sup):
        """TCT's condat of the `Fsa` `sup` (created as `name` by `create`, so TCT's state i is `sup`'s state
        i with the initial one swapped to 0) against the TCT DES `plant`: {state name: sorted event names}
        of the states that disable something. Parsed from printdat's text (pitct's own parser keeps only
        two events per state)."""
        pitct.condat(name + "_DAT", plant, name)
        text = pitct.printdat(name + "_TXT", name + "_DAT", convert=False).text.split("control data:")[1]
        decode = {c: e for e, c in self.code.items()}
        init = sup.initial or 0
        swap = lambda x: init if x == 0 else (0 if x == init else x)
        out, state = {}, None
        if text.split() == ["empty."]:
            # Nothing disabled anywhere: TCT writes the word instead of a list.
            return out
        for token in text.split():
            if token.endswith(":"):
                state = sup.states[swap(int(token[:-1]))][0]
                out[state] = []
            else:
                out[state].append(decode[int(token)])
        return {k: sorted(v) for k, v in out.items() if v}

    def product(self, name, automata):
        """The synchronous product of the `Fsa`s `automata`, as `name`."""
        universe = {e for a in automata for e in a.events}
        names = [self.create(f"{name}_{i}", a, universe) for i, a in enumerate(automata)]
        if len(names) == 1:
            pitct.meet(name, names[0], names[0])
        else:
            pitct.meet(name, *names)
        return name

    def supc(self, name, plants, specs):
        """supC(G, G || E): both lifted to the union of all alphabets, then supcon."""
        universe = {e for a in plants + specs for e in a.events}
        g = [self.create(f"{name}_G{i}", a, universe) for i, a in enumerate(plants)]
        e = [self.create(f"{name}_E{i}", a, universe) for i, a in enumerate(specs)]
        pitct.meet(name + "_G", *(g if len(g) > 1 else g * 2))
        pitct.meet(name + "_E", *(e if len(e) > 1 else e * 2))
        pitct.supcon(name, name + "_G", name + "_E")
        return name


def codegen_json(codegen, args):
    """`codegen synth --json ARGS` as parsed JSON, or None for the verdict that no supervisor exists (exit 1,
    said on stderr, nothing on stdout)."""
    out = subprocess.run([codegen, "synth", "--json", *args], check=False, capture_output=True, text=True)
    if out.returncode not in (0, 1):
        raise RuntimeError(f"codegen synth {' '.join(args)}: {out.stderr}")
    if out.returncode == 1 and not out.stdout.strip() and "no supervisor exists" in out.stderr:
        return None
    import json

    return json.loads(out.stdout)
