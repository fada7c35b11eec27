// The charting libraries compiled into the binaries (web/CMakeLists.txt): vega, vega-lite and
// vega-embed, minified, in load order. Inlined into `kessler report` files and served by the dashboard.
#pragma once

#include <string>

namespace kessler::web {

// The three scripts concatenated (each preceded by a comment naming it); define vega, vegaLite and
// vegaEmbed as globals when run in a page.
const std::string& charting_scripts();

}  // namespace kessler::web
