// The dashboard's HTML pages. Each is a shell whose script reads the JSON API (http_api.cpp); the
// charting scripts come from /assets/charts.js, compiled into the daemon.
#include <string>

#include "server/run_manager.hpp"
// (after run_manager.hpp: see http_server.cpp)
#include "server/http/http_internal.hpp"
#include "web/figure_page.hpp"

namespace kessler::server::http {
namespace {

std::string page(const std::string& title, const std::string& body, const std::string& script) {
  return "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" +
         web::html_escape(title) + "</title><style>" + web::page_style() +
         "</style><script src=\"/assets/charts.js\"></script></head><body>" + body + "<script>" + script +
         "</script></body></html>\n";
}

// Helpers every page script uses.
const char* const kCommonScript = R"js(
const $ = (id) => document.getElementById(id);
function esc(v) { return String(v).replace(/[&<>"']/g, (c) => ({'&':'&amp;','<':'&lt;','>':'&gt;','"':'&quot;',"'":'&#39;'})[c]); }
async function api(path) {
  const r = await fetch(path);
  const body = await r.json();
  if (!r.ok) throw new Error(body.error || r.statusText);
  return body;
}
function showError(e) { const el = $('error'); if (el) el.textContent = String(e.message || e); }
function fmtTime(unix) { return unix > 0 ? new Date(unix * 1000).toISOString().replace('.000Z', 'Z') : '-'; }
function pct(p) { return p && p.total_steps > 0 ? (100 * p.step / p.total_steps).toFixed(1) + ' %' : '-'; }
const TERMINAL = ['RUN_STATE_SUCCEEDED', 'RUN_STATE_FAILED', 'RUN_STATE_CANCELLED'];
function stateName(s) { return String(s).replace('RUN_STATE_', '').toLowerCase(); }
)js";

const char* const kIndexBody = R"html(
<h1>Kessler runs</h1><p id="error" class="error"></p>
<h2>Runs</h2><table><thead><tr><th>run</th><th>name</th><th>state</th><th>progress</th><th>created</th>
<th>conjunctions</th></tr></thead><tbody id="runs"></tbody></table>
<p><button id="more-runs" hidden>more runs</button></p>
<h2>Ensembles</h2><table><thead><tr><th>ensemble</th><th>name</th><th>state</th><th>members</th><th>finished</th>
</tr></thead><tbody id="ensembles"></tbody></table>
)html";

const char* const kIndexScript = R"js(
let runsToken = '';
async function loadRuns() {
  const page = await api('/api/runs?page_size=100' + (runsToken ? '&page_token=' + encodeURIComponent(runsToken) : ''));
  for (const r of page.runs) {
    const tr = document.createElement('tr');
    const n = r.summary && r.summary.steps > 0 ? r.summary.conjunctions : '-';
    tr.innerHTML = `<td><a href="/runs/${r.id}">${r.id}</a></td><td>${esc(r.name)}</td><td>${stateName(r.state)}</td>` +
      `<td>${pct(r.progress)}</td><td>${fmtTime(r.created_unix_s)}</td><td>${n}</td>`;
    $('runs').appendChild(tr);
  }
  runsToken = page.next_page_token;
  $('more-runs').hidden = !runsToken;
}
async function loadEnsembles() {
  const page = await api('/api/ensembles?page_size=100');
  for (const e of page.ensembles) {
    const tr = document.createElement('tr');
    tr.innerHTML = `<td><a href="/ensembles/${e.id}">${e.id}</a></td><td>${esc(e.name)}</td><td>${stateName(e.state)}</td>` +
      `<td>${e.members}</td><td>${e.finished}</td>`;
    $('ensembles').appendChild(tr);
  }
}
$('more-runs').onclick = () => loadRuns().catch(showError);
Promise.all([loadRuns(), loadEnsembles()]).catch(showError);
)js";

const char* const kRunBody = R"html(
<p><a href="/">all runs</a></p><h1 id="title">run</h1><p id="error" class="error"></p>
<table id="facts"></table>
<h2>Conjunctions</h2>
<form id="filters" class="filters">
<label>kappa &le; <input name="kappa_max" size="5"></label>
<label>object <input name="object_id" size="8"></label>
<label>from [s] <input name="time_min_s" size="8"></label><label>to [s] <input name="time_max_s" size="8"></label>
<label><input type="checkbox" name="collisions_only"> collisions only</label>
<label><input type="checkbox" name="closest_per_pair"> closest per pair</label>
<button type="submit">filter</button> <a id="csv" href="#">download CSV</a></form>
<p id="conj-count"></p>
<table><thead><tr><th class="sortable" data-col="seq">seq</th><th class="sortable" data-col="tca_s">TCA [s]</th>
<th>object 1</th><th>object 2</th><th class="sortable" data-col="miss_distance_m">miss distance [m]</th>
<th>relative speed [m/s]</th><th class="sortable" data-col="kappa">kappa</th><th>kind</th></tr></thead>
<tbody id="conjunctions"></tbody></table>
<p><button id="prev" disabled>previous</button> <button id="next" disabled>next</button></p>
<h2>Figures</h2><div id="figures"></div>
)html";

const char* const kRunScript = R"js(
const runId = Number(location.pathname.split('/')[2]);
let order = { by: 'seq', desc: false };
let tokens = [''];
function filterQuery() {
  const q = new URLSearchParams();
  const f = new FormData($('filters'));
  for (const [k, v] of f.entries()) if (v !== '') q.set(k, v === 'on' ? 'true' : v);
  q.set('order_by', order.by);
  if (order.desc) q.set('descending', 'true');
  return q;
}
async function loadConjunctions() {
  const q = filterQuery();
  q.set('page_size', '50');
  const token = tokens[tokens.length - 1];
  if (token) q.set('page_token', token);
  const page = await api(`/api/runs/${runId}/conjunctions?` + q);
  const body = $('conjunctions');
  body.replaceChildren();
  for (const c of page.conjunctions) {
    const tr = document.createElement('tr');
    tr.innerHTML = `<td>${c.seq}</td><td>${c.tca_s.toFixed(3)}</td><td>${c.id1} ${esc(c.name1)}</td>` +
      `<td>${c.id2} ${esc(c.name2)}</td><td>${c.miss_distance_m.toFixed(1)}</td>` +
      `<td>${c.relative_speed_m_s.toFixed(1)}</td><td>${c.kappa.toFixed(3)}</td><td>${c.kind}</td>`;
    body.appendChild(tr);
  }
  $('conj-count').textContent = `${page.total} matching; page ${tokens.length}`;
  $('next').disabled = !page.next_page_token;
  $('next').dataset.token = page.next_page_token;
  $('prev').disabled = tokens.length < 2;
  const csv = filterQuery(); csv.set('format', 'csv');
  $('csv').href = `/api/runs/${runId}/conjunctions?` + csv;
}
$('filters').onsubmit = (e) => { e.preventDefault(); tokens = ['']; loadConjunctions().catch(showError); };
$('next').onclick = () => { tokens.push($('next').dataset.token); loadConjunctions().catch(showError); };
$('prev').onclick = () => { tokens.pop(); loadConjunctions().catch(showError); };
for (const th of document.querySelectorAll('th.sortable')) th.onclick = () => {
  order = { by: th.dataset.col, desc: order.by === th.dataset.col ? !order.desc : false };
  tokens = ['']; loadConjunctions().catch(showError);
};
async function loadFigures() {
  const compare = new URLSearchParams(location.search).get('compare');
  const data = await api(`/api/runs/${runId}/figures` + (compare ? '?compare=' + encodeURIComponent(compare) : ''));
  await kesslerRenderFigures($('figures'), data.figures);
}
function showRun(run) {
  $('title').textContent = `run ${run.id}` + (run.name ? ` (${run.name})` : '') + `: ${stateName(run.state)}`;
  const rows = [['progress', pct(run.progress) + (run.progress ? `, step ${run.progress.step} of ${run.progress.total_steps}, ${run.progress.objects_alive} objects alive` : '')],
    ['created', fmtTime(run.created_unix_s)], ['started', fmtTime(run.started_unix_s)], ['finished', fmtTime(run.finished_unix_s)]];
  if (run.error) rows.push(['error', run.error]);
  if (run.summary && run.summary.events_digest) rows.push(['events digest', run.summary.events_digest], ['state digest', run.summary.state_digest]);
  $('facts').innerHTML = rows.map(([k, v]) => `<tr><th>${k}</th><td id="fact-${k.replace(' ', '-')}">${esc(v)}</td></tr>`).join('');
}
// Live progress by polling; the conjunctions and figures are read again when the run ends.
async function poll() {
  const run = await api(`/api/runs/${runId}`);
  showRun(run);
  if (!TERMINAL.includes(run.state)) { setTimeout(() => poll().then(refreshIfEnded).catch(showError), 2000); }
  return run;
}
let wasRunning = false;
function refreshIfEnded(run) {
  if (!TERMINAL.includes(run.state)) { wasRunning = true; return; }
  if (wasRunning) { wasRunning = false; loadConjunctions().catch(showError); loadFigures().catch(showError); }
}
poll().then((run) => { wasRunning = !TERMINAL.includes(run.state); return Promise.all([loadConjunctions(), loadFigures()]); })
  .catch(showError);
)js";

const char* const kEnsembleBody = R"html(
<p><a href="/">all runs</a></p><h1 id="title">ensemble</h1><p id="error" class="error"></p>
<h2>Members</h2><table><thead><tr><th>index</th><th>run</th><th>seed</th><th>state</th><th>events digest</th></tr></thead>
<tbody id="members"></tbody></table>
<h2>Figures</h2><div id="figures"></div>
)html";

const char* const kEnsembleScript = R"js(
const ensembleId = Number(location.pathname.split('/')[2]);
async function load() {
  const e = await api(`/api/ensembles/${ensembleId}`);
  $('title').textContent = `ensemble ${e.id}` + (e.name ? ` (${e.name})` : '') +
    `: ${stateName(e.state)}, ${e.finished} of ${e.members} members ended`;
  $('members').innerHTML = (e.member || []).map((m) => `<tr><td>${m.member_index}</td><td><a href="/runs/${m.run_id}">${m.run_id}</a></td>` +
    `<td>${m.seed}</td><td>${stateName(m.state)}</td><td>${esc(m.events_digest)}</td></tr>`).join('');
  const data = await api(`/api/ensembles/${ensembleId}/figures`);
  await kesslerRenderFigures($('figures'), data.figures);
}
load().catch(showError);
)js";

void serve(httplib::Server& server, const char* pattern, std::string html) {
  server.Get(pattern, [html = std::move(html)](const httplib::Request& req, httplib::Response& res) {
    guarded(res, [&] {
      Params p(req, {"compare"});
      res.set_content(html, "text/html; charset=utf-8");
    });
  });
}

}  // namespace

void add_page_routes(httplib::Server& server) {
  const std::string common = kCommonScript;
  serve(server, "/", page("Kessler", kIndexBody, common + kIndexScript));
  serve(server, R"(/runs/(\d+))", page("Kessler run", kRunBody, common + kRunScript));
  serve(server, R"(/ensembles/(\d+))", page("Kessler ensemble", kEnsembleBody, common + kEnsembleScript));
}

}  // namespace kessler::server::http
