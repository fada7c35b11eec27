// CDM in XML (CCSDS NDM/XML): the same keywords as elements, grouped in blocks. Read with pugixml,
// which never expands entities; DOCTYPE declarations are refused outright.
#include <algorithm>
#include <cstring>

#include <pugixml.hpp>

#include "core/assessment/cdm.hpp"

namespace kessler::assessment {

namespace {

std::string normalise(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  std::string out(s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1));
  for (std::size_t at = out.find("\xE2\x88\x92"); at != std::string::npos; at = out.find("\xE2\x88\x92", at))
    out.replace(at, 3, "-");
  return out;
}

// 1-based line of a byte offset (offsets from pugixml's offset_debug).
struct LineIndex {
  std::vector<std::size_t> starts;
  explicit LineIndex(std::string_view text) {
    starts.push_back(0);
    for (std::size_t i = 0; i < text.size(); ++i)
      if (text[i] == '\n') starts.push_back(i + 1);
  }
  std::size_t line_of(std::ptrdiff_t offset) const {
    if (offset < 0) return 0;
    return static_cast<std::size_t>(
        std::upper_bound(starts.begin(), starts.end(), static_cast<std::size_t>(offset)) - starts.begin());
  }
};

// Leaf elements (a keyword with its text) below node, in document order, into section.
void collect_leaves(const pugi::xml_node& node, const LineIndex& lines, std::vector<CdmField>& section) {
  for (const pugi::xml_node& child : node.children()) {
    if (child.type() != pugi::node_element) continue;
    if (child.first_child().type() == pugi::node_element) {
      collect_leaves(child, lines, section);
      continue;
    }
    section.push_back({child.name(), normalise(child.text().get()), child.attribute("units").value(),
                       lines.line_of(child.offset_debug())});
  }
}

}  // namespace

bool read_cdm_xml(std::string_view text, Cdm& out, std::vector<CdmError>& errors) {
  out = Cdm{};
  if (text.size() > kMaxCdmBytes) {
    errors.push_back(cdm_error(0, "",
                               "message of " + std::to_string(text.size()) + " bytes, over the limit of " +
                                   std::to_string(kMaxCdmBytes)));
    return false;
  }
  const LineIndex lines(text);
  for (const char* declaration : {"<!DOCTYPE", "<!ENTITY"}) {
    const auto at = text.find(declaration);
    if (at != std::string_view::npos) {
      errors.push_back(cdm_error(lines.line_of(static_cast<std::ptrdiff_t>(at)), "",
                                 std::string(declaration + 2) + " declarations are not accepted in a CDM"));
      return false;
    }
  }
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed =
      doc.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!parsed) {
    errors.push_back(
        cdm_error(lines.line_of(parsed.offset), "", std::string("XML: ") + parsed.description()));
    return false;
  }
  const pugi::xml_node root = doc.child("cdm");
  if (!root) {
    errors.push_back(cdm_error(1, "", "no <cdm> root element"));
    return false;
  }
  const std::size_t root_line = lines.line_of(root.offset_debug());
  out.header.push_back({"CCSDS_CDM_VERS", root.attribute("version").value(), "", root_line});
  collect_leaves(root.child("header"), lines, out.header);
  const pugi::xml_node body = root.child("body");
  collect_leaves(body.child("relativeMetadataData"), lines, out.relative);
  std::size_t index = 0;
  for (const pugi::xml_node& segment : body.children("segment")) {
    if (index == 2) {
      errors.push_back(cdm_error(lines.line_of(segment.offset_debug()), "segment", "more than two objects"));
      return false;
    }
    collect_leaves(segment, lines, out.objects[index++]);
  }
  return true;
}

std::string_view cdm_xml_block(std::string_view k) {
  static constexpr std::array<std::string_view, 10> kOd = {
      "TIME_LASTOB_START", "TIME_LASTOB_END",  "RECOMMENDED_OD_SPAN", "ACTUAL_OD_SPAN",     "OBS_AVAILABLE",
      "OBS_USED",          "TRACKS_AVAILABLE", "TRACKS_USED",         "RESIDUALS_ACCEPTED", "WEIGHTED_RMS"};
  static constexpr std::array<std::string_view, 8> kAdditional = {"AREA_PC",
                                                                  "AREA_DRG",
                                                                  "AREA_SRP",
                                                                  "MASS",
                                                                  "CD_AREA_OVER_MASS",
                                                                  "CR_AREA_OVER_MASS",
                                                                  "THRUST_ACCELERATION",
                                                                  "SEDR"};
  if (k.starts_with("RELATIVE_POSITION_") || k.starts_with("RELATIVE_VELOCITY_"))
    return "relativeStateVector";
  if (k == "X" || k == "Y" || k == "Z" || k == "X_DOT" || k == "Y_DOT" || k == "Z_DOT") return "stateVector";
  if (std::find(kOd.begin(), kOd.end(), k) != kOd.end()) return "odParameters";
  if (std::find(kAdditional.begin(), kAdditional.end(), k) != kAdditional.end())
    return "additionalParameters";
  if (k.size() >= 3 && k[0] == 'C' && k.find('_') != std::string_view::npos && k != "CATALOG_NAME" &&
      k != "COVARIANCE_METHOD" && k != "COMMENT")
    return "covarianceMatrix";
  return "";
}

namespace {

void append_leaf(pugi::xml_node parent, const CdmField& f) {
  pugi::xml_node node = parent.append_child(f.keyword.c_str());
  if (!f.unit.empty()) node.append_attribute("units") = f.unit.c_str();
  node.text() = f.value.c_str();
}

// An object's fields: metadata (up to the first data keyword), then data in its sub-blocks.
void append_object(pugi::xml_node body, const std::vector<CdmField>& fields) {
  pugi::xml_node segment = body.append_child("segment");
  pugi::xml_node metadata = segment.append_child("metadata");
  pugi::xml_node data;
  pugi::xml_node block;
  std::string_view block_name;
  for (const CdmField& f : fields) {
    const std::string_view name = f.keyword == "COMMENT" ? block_name : cdm_xml_block(f.keyword);
    if (!data && f.keyword != "COMMENT" && !name.empty()) data = segment.append_child("data");
    if (!data) {
      append_leaf(metadata, f);
      continue;
    }
    if (name.empty()) {
      append_leaf(data, f);
      continue;
    }
    if (!block || name != block_name) {
      block = data.append_child(std::string(name).c_str());
      block_name = block.name();
    }
    append_leaf(block, f);
  }
}

}  // namespace

std::string write_cdm_xml(const Cdm& cdm) {
  pugi::xml_document doc;
  pugi::xml_node decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version") = "1.0";
  decl.append_attribute("encoding") = "UTF-8";
  pugi::xml_node root = doc.append_child("cdm");
  root.append_attribute("id") = "CCSDS_CDM_VERS";
  const CdmField* version = Cdm::find(cdm.header, "CCSDS_CDM_VERS");
  root.append_attribute("version") = version ? version->value.c_str() : "1.0";
  pugi::xml_node header = root.append_child("header");
  for (const CdmField& f : cdm.header)
    if (f.keyword != "CCSDS_CDM_VERS") append_leaf(header, f);
  pugi::xml_node body = root.append_child("body");
  pugi::xml_node relative = body.append_child("relativeMetadataData");
  pugi::xml_node state;
  for (const CdmField& f : cdm.relative) {
    if (cdm_xml_block(f.keyword) == "relativeStateVector") {
      if (!state) state = relative.append_child("relativeStateVector");
      append_leaf(state, f);
    } else {
      append_leaf(relative, f);
    }
  }
  for (const auto& object : cdm.objects) append_object(body, object);
  struct Writer : pugi::xml_writer {
    std::string text;
    void write(const void* data, std::size_t size) override {
      text.append(static_cast<const char*>(data), size);
    }
  } writer;
  doc.save(writer, "  ");
  return writer.text;
}

}  // namespace kessler::assessment
