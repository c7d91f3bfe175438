"""The structure of Studio 5000 `.L5X` project files, as Rockwell's import/export manual
(publication 1756-RM084) describes it; Rockwell publishes no schema. Written independently of the
writer (`codegen/src/scan/vendor/rockwell.rs`): it reads the XML, never our program IR.

Checked per file: the root element `RSLogix5000Content` with its attributes, one `Controller` whose
sections come in the importer's order, every name valid for Logix, every data type known (atomic,
built-in, a user data type or an Add-On Instruction of the file), every BIT member's host present,
every ST line in CDATA, every tag an ST line or a rung reads declared in its scope (an Add-On
Instruction's parameters and local tags; a program's tags and the controller's), every member read
of a structure, timer or instruction instance, every rung made of known instructions, every
routine ST or ladder (RLL), every `JSR` calling a routine of its own program (not itself; none in an
Add-On Instruction, which cannot call routines) and every routine of a program but its main one
called by a `JSR` (else it never runs), every scheduled program present. Exits 1 listing what is
wrong.

usage: python l5x_structure.py FILE...
"""

import re
import sys

from lxml import etree

NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
ATOMIC = {"bool", "sint", "int", "dint", "lint", "real", "bit"}
BUILTIN = {
    "timer": {"pre", "acc", "en", "tt", "dn"},
    "counter": {"pre", "acc", "cu", "cd", "dn", "ov", "un"},
    "fbd_timer": {"enablein", "timerenable", "pre", "reset", "enableout", "acc", "en", "tt", "dn",
                  "status", "instructfault", "presetinv"},
}
ST_WORDS = {"if", "then", "elsif", "else", "end_if", "case", "of", "end_case", "for", "to", "by", "do",
            "end_for", "while", "end_while", "repeat", "until", "end_repeat", "exit", "return", "and",
            "or", "xor", "not", "mod"}
ST_INSTRUCTIONS = {"tonr": "fbd_timer", "tofr": "fbd_timer", "rtor": "fbd_timer"}
RLL_BIT = {"XIC", "XIO", "OTE", "OTL", "OTU"}
ORDER = ["RedundancyInfo", "Security", "SafetyInfo", "DataTypes", "Modules",
         "AddOnInstructionDefinitions", "Tags", "Programs", "Tasks"]
PATH = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)((?:\s*\.\s*[A-Za-z_][A-Za-z0-9_]*)*)(\s*\()?")


def valid(name):
    return (name is not None and len(name) <= 40 and NAME.match(name) is not None
            and "__" not in name and not name.endswith("_"))


def check(path):
    errors = []

    def bad(msg):
        errors.append(f"{path}: {msg}")

    root = etree.parse(path, etree.XMLParser(strip_cdata=False)).getroot()
    if root.tag != "RSLogix5000Content":
        bad(f"root element {root.tag}")
        return errors
    for a in ("SchemaRevision", "SoftwareRevision", "TargetName", "TargetType", "ContainsContext"):
        if a not in root.attrib:
            bad(f"root without {a}")
    controllers = root.findall("Controller")
    if len(controllers) != 1:
        bad(f"{len(controllers)} Controller elements")
        return errors
    ctrl = controllers[0]
    seen = [c.tag for c in ctrl if isinstance(c.tag, str) and c.tag in ORDER]
    if seen != sorted(seen, key=ORDER.index):
        bad(f"Controller sections out of order: {seen}")
    for e in ctrl.iter():
        if isinstance(e.tag, str) and "Name" in e.attrib and not valid(e.get("Name")):
            bad(f"{e.tag} name {e.get('Name')!r} is no Logix name")

    # Types: members (lower-case name -> type) of every structured type.
    members = {k: {m: "dint" for m in v} for k, v in BUILTIN.items()}
    for dt in ctrl.findall("DataTypes/DataType"):
        ms = {m.get("Name").lower(): m.get("DataType").lower() for m in dt.findall("Members/Member")}
        members[dt.get("Name").lower()] = ms
        for m in dt.findall("Members/Member"):
            if m.get("DataType") == "BIT" and (m.get("Target") or "").lower() not in ms:
                bad(f"{dt.get('Name')}.{m.get('Name')}: no host {m.get('Target')}")
    aois = {}
    for aoi in ctrl.findall("AddOnInstructionDefinitions/AddOnInstructionDefinition"):
        params = {p.get("Name").lower(): p for p in aoi.findall("Parameters/Parameter")}
        members[aoi.get("Name").lower()] = {n: p.get("DataType").lower() for n, p in params.items()}
        aois[aoi.get("Name").lower()] = params
    known = ATOMIC | set(members)
    for e in ctrl.iter("Member", "Parameter", "LocalTag", "Tag"):
        if e.get("DataType", "").lower() not in known:
            bad(f"{e.tag} {e.get('Name')}: unknown data type {e.get('DataType')}")

    def scope_of(tags):
        return {t.get("Name").lower(): t.get("DataType").lower() for t in tags}

    def resolve(where, head, tail, scope):
        ty = scope.get(head.lower())
        if ty is None:
            bad(f"{where}: '{head}' is not declared")
            return
        for m in [m.strip() for m in tail.split(".") if m.strip()]:
            if ty not in members or m.lower() not in members[ty]:
                bad(f"{where}: '{head}{tail}': {ty} has no member {m}")
                return
            ty = members[ty][m.lower()]

    def st(where, routine, scope):
        lines = routine.findall("STContent/Line")
        for line in lines:
            if "<![CDATA[" not in etree.tostring(line, encoding="unicode"):
                bad(f"{where} line {line.get('Number')}: not in CDATA")
        text = re.sub(r"\(\*.*?\*\)", " ", "\n".join(line.text or "" for line in lines), flags=re.S)
        if "#" in text:
            bad(f"{where}: a '#' literal (Logix ST has no typed literals)")
        for m in PATH.finditer(text):
            head, tail, call = m.group(1), m.group(2), m.group(3)
            if head.lower() in ST_WORDS or (text[max(0, m.start() - 1)] in "0123456789"):
                continue
            if call and not tail and (head.lower() in ST_INSTRUCTIONS or head.lower() in aois):
                continue
            resolve(where, head, tail, scope)

    def rll(where, routine, scope, callable_routines, calls):
        for rung in routine.findall("RLLContent/Rung"):
            text_el = rung.find("Text")
            raw = etree.tostring(text_el, encoding="unicode") if text_el is not None else ""
            if "<![CDATA[" not in raw:
                bad(f"{where} rung {rung.get('Number')}: text not in CDATA")
            text = (text_el.text or "").strip() if text_el is not None else ""
            if not text.endswith(";"):
                bad(f"{where} rung {rung.get('Number')}: no ';'")
            rest = re.sub(r"[A-Z]+\([^()]*\)", "", text[:-1])
            if rest.replace("[", "").replace("]", "").replace(",", "").strip():
                bad(f"{where} rung {rung.get('Number')}: '{rest}' is no instruction")
            for ins, args in re.findall(r"([A-Z]+)\(([^()]*)\)", text):
                args = [a.strip() for a in args.split(",")]
                if ins in RLL_BIT and len(args) == 1:
                    m = PATH.fullmatch(args[0])
                    if m is None:
                        bad(f"{where}: {ins}({args[0]})")
                    else:
                        resolve(where, m.group(1), m.group(2), scope)
                elif ins == "TON" and len(args) == 3:
                    if scope.get(args[0].lower()) != "timer" or not args[1].isdigit():
                        bad(f"{where}: TON({','.join(args)}) needs a TIMER tag and a preset")
                elif ins == "JSR" and len(args) == 2 and args[1] == "0":
                    if callable_routines is None:
                        bad(f"{where}: JSR in an Add-On Instruction (it cannot call routines)")
                    elif args[0] not in callable_routines or args[0] == routine.get("Name"):
                        bad(f"{where}: JSR({args[0]},0) calls no other routine of its program")
                    calls.add(args[0])
                else:
                    bad(f"{where}: unknown instruction {ins}({','.join(args)})")

    def routines(where, owner, scope, callable_routines):
        """Checks the routines of `owner`; returns the routines their JSRs call."""
        calls = set()
        for r in owner.findall("Routines/Routine"):
            kind = r.get("Type")
            w = f"{where}/{r.get('Name')}"
            if kind == "ST":
                st(w, r, scope)
            elif kind == "RLL":
                rll(w, r, scope, callable_routines, calls)
            else:
                bad(f"{w}: routine type {kind}")
        return calls

    for aoi in ctrl.findall("AddOnInstructionDefinitions/AddOnInstructionDefinition"):
        scope = scope_of(aoi.findall("Parameters/Parameter") + aoi.findall("LocalTags/LocalTag"))
        routines(aoi.get("Name"), aoi, scope, None)
    controller = scope_of(ctrl.findall("Tags/Tag"))
    programs = set()
    for prog in ctrl.findall("Programs/Program"):
        programs.add(prog.get("Name"))
        names = {r.get("Name") for r in prog.findall("Routines/Routine")}
        if prog.get("MainRoutineName") not in names:
            bad(f"{prog.get('Name')}: no main routine {prog.get('MainRoutineName')}")
        scope = {**controller, **scope_of(prog.findall("Tags/Tag"))}
        calls = routines(prog.get("Name"), prog, scope, names)
        for name in sorted(names - calls - {prog.get("MainRoutineName")}):
            bad(f"{prog.get('Name')}/{name}: no JSR calls it")
    for sp in ctrl.findall("Tasks/Task/ScheduledPrograms/ScheduledProgram"):
        if sp.get("Name") not in programs:
            bad(f"task schedules unknown program {sp.get('Name')}")
    if not ctrl.findall("Tasks/Task"):
        bad("no task")
    return errors


def main():
    errors = [e for f in sys.argv[1:] for e in check(f)]
    print("\n".join(errors[:50]))
    sys.exit(1 if errors else 0)


if __name__ == "__main__":
    main()
