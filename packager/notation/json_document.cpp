#include "json_document.hpp"

#include "json_positions.hpp"

namespace statepack::packager {
namespace {

using Json = nlohmann::json;

// nlohmann's DOM builder, except that a parse error is recorded with its position instead of thrown.
class RecordingSax {
 public:
  explicit RecordingSax(Json& root) : dom_(root, false) {}

  bool null() { return dom_.null(); }
  bool boolean(bool v) { return dom_.boolean(v); }
  bool number_integer(Json::number_integer_t v) { return dom_.number_integer(v); }
  bool number_unsigned(Json::number_unsigned_t v) { return dom_.number_unsigned(v); }
  bool number_float(Json::number_float_t v, const std::string& s) { return dom_.number_float(v, s); }
  bool string(std::string& v) { return dom_.string(v); }
  bool binary(Json::binary_t& v) { return dom_.binary(v); }
  bool start_object(std::size_t n) { return dom_.start_object(n); }
  bool key(std::string& v) { return dom_.key(v); }
  bool end_object() { return dom_.end_object(); }
  bool start_array(std::size_t n) { return dom_.start_array(n); }
  bool end_array() { return dom_.end_array(); }
  template <class Exception>
  bool parse_error(std::size_t position, const std::string& token, const Exception& ex) {
    failed = true;
    offset = position > 0 ? position - 1 : 0;
    std::string what = ex.what();
    if (ex.id == 406) {  // nlohmann: "number overflow parsing '1e999'"; point at its first digit
      offset = offset + 1 >= token.size() ? offset + 1 - token.size() : 0;
      message = "number '" + token + "' is out of range (beyond a double's largest value)";
      return false;
    }
    // "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error while parsing..."
    auto syntax = what.find("syntax error");
    message = "invalid JSON: " + (syntax != std::string::npos ? what.substr(syntax) : what);
    return false;
  }

  bool failed = false;
  size_t offset = 0;
  std::string message;

 private:
  nlohmann::detail::json_sax_dom_parser<Json> dom_;
};

}  // namespace

std::string_view strip_utf8_bom(std::string_view text) {
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return text;
}

JsonDocument parse_json_document(std::string_view text) {
  JsonDocument doc;
  std::vector<StructureProblem> problems = check_json_structure(text);
  for (const auto& p : problems)
    if (p.kind == StructureProblem::Kind::too_deep) {
      doc.errors.push_back({p.offset, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                                          " levels (render-state notation needs fewer than ten)"});
      return doc;
    }
  RecordingSax sax(doc.root);
  bool ok = Json::sax_parse(text.begin(), text.end(), &sax, nlohmann::detail::input_format_t::json, true);
  if (!ok || sax.failed) {
    doc.errors.push_back({sax.offset, sax.failed ? sax.message : "invalid JSON"});
    doc.root = Json();
    return doc;
  }
  doc.parsed = true;
  JsonPositions positions(text);
  for (const auto& p : problems) {
    TextPosition first = positions.position_at(p.first_offset);
    doc.errors.push_back({p.offset, "duplicate key '" + p.key + "' (first at line " +
                                        std::to_string(first.line) + ", column " +
                                        std::to_string(first.column) + ")"});
  }
  return doc;
}

}  // namespace statepack::packager
