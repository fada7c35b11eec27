// What a page needs to draw figures, shared by `kessler report` and the dashboard: the render script
// (after the charting scripts of assets.hpp) and the style. The script defines
// kesslerRenderFigures(container, figures) for figures [{id, title, partial, spec}], draws each with
// vega-embed (SVG), and writes what it drew into <pre id="kessler-render-results" hidden>: per figure
// the marks by kind (a line or area path counts once, every other mark item once), the console errors
// and failures seen on the page, and done: true. Browser tests read it from the DOM.
#pragma once

#include <string>

namespace kessler::web {

const std::string& render_script();
const std::string& page_style();
// JSON text made safe inside a <script> element ("</" cannot close it).
std::string script_safe(const std::string& json);
// Text made safe inside HTML elements and attribute values.
std::string html_escape(const std::string& text);

}  // namespace kessler::web
