#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

struct Entry {
  std::string summary;
  BenchMain main;
};

std::map<std::string, Entry>& registry() {
  static std::map<std::string, Entry> entries;
  return entries;
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

Registration::Registration(const char* name, const char* summary, BenchMain main) {
  registry()[name] = Entry{summary, main};
}

Args::Args(int argc, char** argv) {
  for (int i = 0; i < argc; ++i) {
    std::string key = argv[i];
    if (key.rfind("--", 0) != 0) {
      std::cerr << "kessler-bench: unexpected argument '" << key << "'\n";
      std::exit(2);
    }
    if (i + 1 < argc && std::string(argv[i + 1]).rfind("--", 0) != 0)
      values_[key] = argv[++i];
    else
      values_[key] = "";
  }
}

bool Args::has(const std::string& key) const {
  return values_.count(key) > 0;
}

std::string Args::get(const std::string& key, const std::string& fallback) const {
  auto it = values_.find(key);
  return it == values_.end() ? fallback : it->second;
}

double Args::get_double(const std::string& key, double fallback) const {
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  char* end = nullptr;
  double v = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end != '\0' || !std::isfinite(v)) {
    std::cerr << "kessler-bench: " << key << " needs a number, got '" << it->second << "'\n";
    std::exit(2);
  }
  return v;
}

std::int64_t Args::get_int(const std::string& key, std::int64_t fallback) const {
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  char* end = nullptr;
  long long v = std::strtoll(it->second.c_str(), &end, 10);
  if (it->second.empty() || *end != '\0') {
    std::cerr << "kessler-bench: " << key << " needs an integer, got '" << it->second << "'\n";
    std::exit(2);
  }
  return v;
}

void Args::allow_only(const std::vector<std::string>& known) const {
  for (const auto& [key, value] : values_)
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      std::cerr << "kessler-bench: unknown option " << key << "\n";
      std::exit(2);
    }
}

JsonLine& JsonLine::add(const std::string& key, double value) {
  std::ostringstream s;
  s.precision(6);
  s << '"' << json_escape(key) << "\": ";
  if (std::isfinite(value))
    s << value;
  else
    s << "null";
  fields_.push_back(s.str());
  return *this;
}

JsonLine& JsonLine::add(const std::string& key, std::int64_t value) {
  fields_.push_back('"' + json_escape(key) + "\": " + std::to_string(value));
  return *this;
}

JsonLine& JsonLine::add(const std::string& key, const std::string& value) {
  fields_.push_back('"' + json_escape(key) + "\": \"" + json_escape(value) + '"');
  return *this;
}

std::string JsonLine::str() const {
  std::string out = "{";
  for (std::size_t i = 0; i < fields_.size(); ++i) out += (i ? ", " : "") + fields_[i];
  return out + "}";
}

void JsonLine::print() const {
  std::cout << str() << std::endl;
}

double median(std::vector<double> values) {
  if (values.empty()) return NAN;
  std::sort(values.begin(), values.end());
  std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace kessler::bench

int main(int argc, char** argv) {
  using kessler::bench::registry;
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    std::cout << "usage: kessler-bench <benchmark> [--option value ...]\n\nbenchmarks:\n";
    for (const auto& [name, entry] : registry())
      std::cout << "  " << name << "\n      " << entry.summary << "\n";
    return argc < 2 ? 2 : 0;
  }
  auto it = registry().find(argv[1]);
  if (it == registry().end()) {
    std::cerr << "kessler-bench: unknown benchmark '" << argv[1] << "' (see kessler-bench --help)\n";
    return 2;
  }
  return it->second.main(argc - 2, argv + 2);
}
