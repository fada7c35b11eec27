// OMM XML (CCSDS NDM/XML, as CelesTrak and the CCSDS examples write it). pugixml: a small, non-validating
// DOM parser that never loads external entities; a document type declaration is refused outright, since
// catalogs need none and its entity declarations are how "billion laughs" documents blow up.
#include <pugixml.hpp>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "core/catalog/omm.hpp"
#include "core/catalog/text_fields.hpp"

namespace kessler {
namespace {

// A node's byte offset in the text (pugixml knows it for nodes parsed from a buffer).
std::size_t offset_of(const pugi::xml_node& node) {
  const std::ptrdiff_t offset = node.offset_debug();
  return offset < 0 ? 0 : static_cast<std::size_t>(offset);
}

// Element nesting deeper than this is refused: OMM needs 5 (ndm, omm, body, segment, data, field).
constexpr int kMaxDepth = 64;

// Finds the <omm> messages in document order and refuses nesting deeper than kMaxDepth, without
// recursion (pugixml's walker keeps its own stack), so a million nested elements cost no stack.
class MessageFinder : public pugi::xml_tree_walker {
 public:
  bool for_each(pugi::xml_node& node) override {
    if (node.type() == pugi::node_element && depth() >= kMaxDepth) {
      too_deep = node;
      return false;
    }
    if (node.type() == pugi::node_element && std::string_view(node.name()) == "omm") messages.push_back(node);
    return true;
  }
  std::vector<pugi::xml_node> messages;
  pugi::xml_node too_deep;
};

// The leaf elements below one message, in document order: the fields, keyed by upper-case name.
std::map<std::string, std::string> message_fields(const pugi::xml_node& message) {
  std::map<std::string, std::string> fields;
  std::vector<pugi::xml_node> pending{message};
  while (!pending.empty()) {
    const pugi::xml_node node = pending.back();
    pending.pop_back();
    if (!node.find_child([](const pugi::xml_node& c) { return c.type() == pugi::node_element; })) {
      if (node != message) fields[text::upper(node.name())] = std::string(text::trim(node.text().get()));
      continue;
    }
    // Children pushed last-first, so they come off in document order (a later duplicate wins).
    std::vector<pugi::xml_node> children;
    for (const pugi::xml_node& c : node.children())
      if (c.type() == pugi::node_element) children.push_back(c);
    pending.insert(pending.end(), children.rbegin(), children.rend());
  }
  return fields;
}

}  // namespace

ElementSetText parse_omm_xml(std::string_view text, const std::string& source) {
  ElementSetText out;
  text::LineCounter lines(text.data(), text.size());
  auto refuse = [&](std::size_t offset, const std::string& why) {
    const std::size_t line = lines.line_at(offset);
    out.problems.push_back({source, line, "xml", "not OMM XML: line " + std::to_string(line) + ": " + why});
    return out;
  };
  pugi::xml_document doc;
  // parse_doctype keeps a DOCTYPE as a node, so that it can be refused below rather than skipped.
  const pugi::xml_parse_result parsed = doc.load_buffer(
      text.data(), text.size(), pugi::parse_default | pugi::parse_doctype, pugi::encoding_utf8);
  if (!parsed)
    return refuse(static_cast<std::size_t>(std::max<std::ptrdiff_t>(parsed.offset, 0)), parsed.description());
  for (const pugi::xml_node& node : doc.children())
    if (node.type() == pugi::node_doctype)
      return refuse(offset_of(node),
                    "a document type declaration (DOCTYPE, entity declarations) is not accepted");
  MessageFinder finder;
  doc.traverse(finder);
  if (finder.too_deep)
    return refuse(offset_of(finder.too_deep),
                  "elements nested deeper than " + std::to_string(kMaxDepth) + " levels");
  for (const pugi::xml_node& message : finder.messages)
    add_omm_fields(out, source, lines.line_at(offset_of(message)), message_fields(message));
  return out;
}

}  // namespace kessler
