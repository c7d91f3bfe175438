// The page of `codegen sim`: every view comes from the JSON API (docs/sim.md); nothing is computed here.
"use strict";

const $ = (id) => document.getElementById(id);
let view = null;

function depth() {
  const d = parseInt($("depth").value, 10);
  return Number.isFinite(d) && d > 0 ? d : 2;
}

async function call(method, path, body) {
  const options = { method, headers: { "Content-Type": "application/json" } };
  if (body !== undefined) {
    options.body = JSON.stringify(body);
  }
  const response = await fetch(path, options);
  const answer = await response.json();
  if (!response.ok) {
    $("status").textContent = answer.error;
    $("status").className = "error";
    return;
  }
  $("status").textContent = answer.ran === null ? "" : "ran " + answer.ran + " events";
  $("status").className = "";
  show(answer);
}

function item(text, className) {
  const li = document.createElement("li");
  li.textContent = text;
  if (className) {
    li.className = className;
  }
  return li;
}

function eventButtons(list, names) {
  list.replaceChildren(
    ...names.map((name) => {
      const li = document.createElement("li");
      const button = document.createElement("button");
      button.textContent = name;
      button.dataset.event = name;
      button.addEventListener("click", () => call("POST", "/api/step", { event: name, depth: depth() }));
      li.appendChild(button);
      return li;
    })
  );
}

function showProgram(program) {
  $("program").hidden = program === null;
  if (program === null) {
    return;
  }
  if (program.Err !== undefined) {
    $("signals").replaceChildren();
    $("rungs").replaceChildren(item("not available: " + program.Err, "error"));
    return;
  }
  const word = program.Ok;
  const memory = word.memory.map((value, k) => ({ name: "memory bit " + k, component: "", direction: "memory", value }));
  $("signals").replaceChildren(
    ...word.signals.concat(memory).map((s) => {
      const tr = document.createElement("tr");
      tr.dataset.signal = s.name;
      for (const text of [s.name, s.component, s.direction, s.value ? "1" : "0"]) {
        const td = document.createElement("td");
        td.textContent = text;
        tr.appendChild(td);
      }
      tr.className = s.value ? "on" : "off";
      return tr;
    })
  );
  $("rungs").replaceChildren(
    ...word.rungs.map((r) => {
      const li = item(r.event + ": " + (r.conducts ? "conducts" : "open"), r.conducts ? "on" : "off");
      li.dataset.rung = r.event;
      return li;
    })
  );
}

function showNet(net) {
  $("net").hidden = net === null;
  if (net === null) {
    return null;
  }
  const div = document.createElement("div");
  div.className = "graph net";
  div.dataset.automaton = "net";
  const h = document.createElement("h3");
  if (net.Err !== undefined) {
    $("net-kind").textContent = "not available";
    $("marking").textContent = net.Err;
    $("fired").textContent = "";
    $("requested").textContent = "";
    h.textContent = "Petri net: " + net.Err;
    div.appendChild(h);
    return div;
  }
  const n = net.Ok;
  const marked = n.places.filter((p) => p.tokens > 0).map((p) => (p.tokens > 1 ? p.id + "×" + p.tokens : p.id));
  const fired = n.transitions.filter((t) => t.fired).map((t) => t.id + (t.event === null ? "" : " (" + t.event + ")"));
  $("net-kind").textContent = n.kind === "plant" ? "the plant net" : "the sequence";
  $("marking").textContent = marked.join(", ") || "none";
  $("fired").textContent = "Fired by the last step: " + (fired.join(", ") || "none") + (n.cut ? " (cut: a cycle)" : "");
  $("requested").textContent = n.kind === "plant" ? "" : "Requested: " + (n.requested.join(", ") || "none");
  h.textContent = "Petri net (" + n.kind + ") — marked ";
  const current = document.createElement("span");
  current.className = "current marking";
  current.textContent = marked.join(", ") || "none";
  h.appendChild(current);
  div.appendChild(h);
  if (n.svg.Ok !== undefined) {
    const img = document.createElement("img");
    img.alt = "Petri net";
    img.src = "data:image/svg+xml;charset=utf-8," + encodeURIComponent(n.svg.Ok);
    div.appendChild(img);
  } else {
    div.appendChild(item(n.svg.Err, "error"));
  }
  return div;
}

function show(state) {
  view = state;
  $("title").textContent = "codegen sim: " + state.name + " (policy " + state.policy + ")";
  eventButtons($("uncontrollable"), state.events.uncontrollable);
  eventButtons($("enabled"), state.events.enabled);
  $("disabled").replaceChildren(
    ...state.events.disabled.map((d) => {
      const li = item(d.event + (d.controllable ? "" : " (uncontrollable)") + " — disabled by ");
      li.dataset.event = d.event;
      const by = document.createElement("span");
      by.className = "by";
      by.textContent = d.by.join(", ");
      li.appendChild(by);
      return li;
    })
  );
  const rows = state.automata.filter((a) => a.coverage !== null);
  $("coverage").replaceChildren(
    ...rows.map((a) => {
      const tr = document.createElement("tr");
      tr.dataset.supervisor = a.name;
      const [taken, all] = a.coverage;
      for (const text of [a.name, taken + " / " + all, Math.round((100 * taken) / Math.max(all, 1)) + " %"]) {
        const td = document.createElement("td");
        td.textContent = text;
        tr.appendChild(td);
      }
      return tr;
    })
  );
  showProgram(state.program);
  if (state.findings.Err !== undefined) {
    $("findings").replaceChildren(item("not available: " + state.findings.Err, "error"));
  } else if (state.findings.Ok.length === 0) {
    $("findings").replaceChildren(item("none"));
  } else {
    $("findings").replaceChildren(
      ...state.findings.Ok.map((f) =>
        item(f.problem + " (" + f.scope + ") on " + f.events.join(", ") + ": " + f.detail +
          (f.at.length ? " — at " + f.at.map(([a, s]) => a + "=" + s).join(" ") : ""))
      )
    );
  }
  $("trace").replaceChildren(
    item("initial state", "user"),
    ...state.trace.map((s) => item(s.event + " (" + s.by + ")", s.by))
  );
  [...$("trace").children].forEach((li, k) => {
    li.dataset.step = k;
    li.addEventListener("click", () => call("POST", "/api/revert", { to: k, depth: depth() }));
  });
  const net = showNet(state.net);
  $("graphs").replaceChildren(
    ...(net === null ? [] : [net]),
    ...state.automata.map((a) => {
      const div = document.createElement("div");
      div.className = "graph " + a.role;
      div.dataset.automaton = a.name;
      const h = document.createElement("h3");
      h.textContent = a.name + " (" + a.role + ", " + a.states + " states) — now ";
      const current = document.createElement("span");
      current.className = "current";
      current.textContent = a.current;
      h.appendChild(current);
      div.appendChild(h);
      if (a.svg.Ok !== undefined) {
        const img = document.createElement("img");
        img.alt = a.name;
        img.src = "data:image/svg+xml;charset=utf-8," + encodeURIComponent(a.svg.Ok);
        div.appendChild(img);
      } else {
        div.appendChild(item(a.svg.Err, "error"));
      }
      if (a.partial) {
        const more = document.createElement("button");
        more.textContent = "showing " + a.shown + " of " + a.states + " states: expand";
        more.addEventListener("click", () => {
          $("depth").value = depth() + 1;
          call("GET", "/api/state?depth=" + depth());
        });
        div.appendChild(more);
      }
      return div;
    })
  );
  document.body.dataset.ready = "true";
}

$("reset").addEventListener("click", () => call("POST", "/api/reset", { depth: depth() }));
$("back").addEventListener("click", () => {
  if (view && view.trace.length > 0) {
    call("POST", "/api/revert", { to: view.trace.length - 1, depth: depth() });
  }
});
$("run").addEventListener("click", () => {
  const n = parseInt($("count").value, 10);
  call("POST", "/api/run", { events: Number.isFinite(n) && n > 0 ? n : 1000, depth: depth() });
});
$("depth").addEventListener("change", () => call("GET", "/api/state?depth=" + depth()));
call("GET", "/api/state?depth=" + depth());
