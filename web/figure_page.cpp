#include "web/figure_page.hpp"

namespace kessler::web {

const std::string& render_script() {
  static const std::string script = R"js(
(function () {
  const results = { done: false, errors: [], figures: {} };
  const originalError = console.error;
  console.error = function () {
    results.errors.push(Array.from(arguments).map(String).join(' '));
    publish();
    originalError.apply(console, arguments);
  };
  window.addEventListener('error', (e) => { results.errors.push('error: ' + e.message); publish(); });
  window.addEventListener('unhandledrejection', (e) => {
    results.errors.push('unhandled rejection: ' + String(e.reason)); publish();
  });
  function countMarks(node, acc) {
    if (!node) return;
    if (node.marktype && node.marktype !== 'group' && node.role === 'mark') {
      const n = node.items ? node.items.length : 0;
      const path = node.marktype === 'line' || node.marktype === 'area' || node.marktype === 'trail';
      acc[node.marktype] = (acc[node.marktype] || 0) + (path ? (n > 0 ? 1 : 0) : n);
    }
    for (const child of node.items || []) countMarks(child, acc);
  }
  function publish() {
    let el = document.getElementById('kessler-render-results');
    if (!el) {
      el = document.createElement('pre');
      el.id = 'kessler-render-results';
      el.hidden = true;
      document.body.appendChild(el);
    }
    el.textContent = JSON.stringify(results);
  }
  window.kesslerRenderFigures = async function (container, figures) {
    results.done = false;
    results.figures = {};
    container.replaceChildren();
    for (const f of figures) {
      const box = document.createElement('section');
      box.className = 'figure';
      const heading = document.createElement('h3');
      heading.textContent = f.title + (f.partial ? ' (partial: drawn from a run that has not ended)' : '');
      const chart = document.createElement('div');
      chart.id = 'figure-' + f.id;
      chart.className = 'chart';
      box.append(heading, chart);
      container.appendChild(box);
      try {
        const embedded = await vegaEmbed(chart, f.spec, { renderer: 'svg', actions: false });
        const marks = {};
        countMarks(embedded.view.scenegraph().root, marks);
        results.figures[f.id] = marks;
      } catch (e) {
        results.errors.push(f.id + ': ' + e);
      }
    }
    results.done = true;
    publish();
  };
})();
)js";
  return script;
}

const std::string& page_style() {
  static const std::string style = R"css(
body { font-family: sans-serif; margin: 1.5em auto; max-width: 1100px; color: #222; background: #fff; }
h1 { font-size: 1.5em; } h2 { font-size: 1.2em; margin-top: 1.6em; border-bottom: 1px solid #ccc; }
h3 { font-size: 1em; }
table { border-collapse: collapse; font-size: 0.9em; }
th, td { border-bottom: 1px solid #ddd; padding: 0.25em 0.6em; text-align: left; }
th.sortable { cursor: pointer; text-decoration: underline dotted; }
pre { background: #f6f6f6; padding: 0.6em; overflow-x: auto; font-size: 0.85em; }
.partial { color: #a15c00; font-weight: bold; }
.figure { margin-bottom: 1.5em; }
.error { color: #b00020; }
form.filters label { margin-right: 0.8em; }
)css";
  return style;
}

std::string script_safe(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (std::size_t i = 0; i < json.size(); ++i) {
    if (json[i] == '<' && i + 1 < json.size() && json[i + 1] == '/') {
      out += "<\\/";
      ++i;
    } else {
      out += json[i];
    }
  }
  return out;
}

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace kessler::web
