#include "core/catalog/flat_json.hpp"

#include <cctype>

namespace kessler {
namespace {

class Reader {
 public:
  explicit Reader(std::string_view t) : text_(t) {}

  bool fail(const std::string& why) {
    if (error_.empty()) error_ = "line " + std::to_string(line_) + ": " + why;
    return false;
  }
  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }
  bool peek(char c) {
    skip_space();
    return pos_ < text_.size() && text_[pos_] == c;
  }
  bool expect(char c) {
    if (!peek(c)) return fail(std::string("expected '") + c + "'");
    ++pos_;
    return true;
  }
  bool string(std::string& out) {
    if (!expect('"')) return false;
    out.clear();
    while (pos_ < text_.size()) {
      char c = text_[pos_++];
      if (c == '"') return true;
      if (c == '\\') {
        if (pos_ >= text_.size()) break;
        char e = text_[pos_++];
        switch (e) {
          case 'n':
            out += '\n';
            break;
          case 't':
            out += '\t';
            break;
          case 'r':
            out += '\r';
            break;
          case 'b':
            out += '\b';
            break;
          case 'f':
            out += '\f';
            break;
          case 'u':
            // Non-ASCII escapes do not occur in element data; keep a placeholder.
            pos_ = std::min(pos_ + 4, text_.size());
            out += '?';
            break;
          default:
            out += e;
        }
      } else {
        if (c == '\n') ++line_;
        out += c;
      }
    }
    return fail("unterminated string");
  }
  // Any value; scalars go to `out`, nested arrays/objects are skipped (out empty).
  bool value(std::string& out) {
    skip_space();
    if (pos_ >= text_.size()) return fail("expected a value");
    const char c = text_[pos_];
    if (c == '"') return string(out);
    if (c == '{' || c == '[') {
      out.clear();
      return skip_nested();
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[pos_])) ||
                                   text_[pos_] == '.' || text_[pos_] == '-' || text_[pos_] == '+'))
      ++pos_;
    if (pos_ == start) return fail("expected a value");
    out = std::string(text_.substr(start, pos_ - start));
    if (out == "null") out.clear();
    return true;
  }
  bool skip_nested() {
    int depth = 0;
    std::string ignored;
    do {
      skip_space();
      if (pos_ >= text_.size()) return fail("unterminated array or object");
      const char c = text_[pos_];
      if (c == '"') {
        if (!string(ignored)) return false;
        continue;
      }
      if (c == '{' || c == '[') ++depth;
      if (c == '}' || c == ']') --depth;
      ++pos_;
    } while (depth > 0);
    return true;
  }
  bool object(FlatJsonObject& obj) {
    skip_space();
    obj.line = line_;
    if (!expect('{')) return false;
    if (peek('}')) {
      ++pos_;
      return true;
    }
    for (;;) {
      std::string key, val;
      if (!string(key) || !expect(':') || !value(val)) return false;
      obj.values[key] = val;
      if (peek(',')) {
        ++pos_;
        continue;
      }
      return expect('}');
    }
  }
  bool document(std::vector<FlatJsonObject>& objects) {
    if (peek('{')) {
      objects.emplace_back();
      if (!object(objects.back())) return false;
    } else {
      if (!expect('[')) return false;
      if (peek(']')) {
        ++pos_;
      } else {
        for (;;) {
          objects.emplace_back();
          if (!object(objects.back())) return false;
          if (peek(',')) {
            ++pos_;
            continue;
          }
          if (!expect(']')) return false;
          break;
        }
      }
    }
    skip_space();
    if (pos_ != text_.size()) return fail("text after the end of the JSON value");
    return true;
  }
  const std::string& error() const { return error_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0, line_ = 1;
  std::string error_;
};

}  // namespace

bool parse_flat_json(std::string_view text, std::vector<FlatJsonObject>& objects, std::string* error) {
  Reader reader(text);
  if (reader.document(objects)) return true;
  if (error) *error = reader.error();
  return false;
}

}  // namespace kessler
