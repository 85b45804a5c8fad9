#include "remote_cache.hpp"

#include <curl/curl.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <hiredis/hiredis.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>
#include <type_traits>
#include <utility>

#include "digest.hpp"
#include "entry_file.hpp"
#include "support/parallel_for.hpp"
#include "support/printable.hpp"

namespace statepack::packager {
namespace fs = std::filesystem;
using detail::printable;
namespace {

bool parse_uint(std::string_view text, uint32_t& out) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && end == text.data() + text.size() && !text.empty();
}

// "a,b(2),c" -> shards with weights.
bool parse_shards(std::string_view text, std::vector<RemoteSpec::Shard>& out, std::string& error) {
  while (!text.empty()) {
    const size_t comma = text.find(',');
    std::string_view item = text.substr(0, comma);
    text = comma == std::string_view::npos ? std::string_view() : text.substr(comma + 1);
    RemoteSpec::Shard shard;
    if (const size_t open = item.find('('); open != std::string_view::npos) {
      uint32_t weight = 0;
      if (item.back() != ')' || !parse_uint(item.substr(open + 1, item.size() - open - 2), weight) ||
          !weight) {
        error = "shards: '" + std::string(item) + "': a weight is a positive whole number in parentheses";
        return false;
      }
      shard.weight = weight;
      item = item.substr(0, open);
    }
    if (item.empty()) {
      error = "shards: an empty shard name";
      return false;
    }
    shard.name = item;
    out.push_back(std::move(shard));
  }
  if (out.empty()) error = "shards: no shard named";
  return !out.empty();
}

bool parse_attribute(std::string_view attribute, RemoteSpec& spec, std::string& error) {
  const size_t eq = attribute.find('=');
  const std::string_view name = attribute.substr(0, eq);
  const std::string_view value = eq == std::string_view::npos ? std::string_view() : attribute.substr(eq + 1);
  if (name == "read-only" && eq == std::string_view::npos) return spec.read_only = true;
  if (name == "connect-timeout" || name == "operation-timeout") {
    uint32_t& ms = name == "connect-timeout" ? spec.connect_timeout_ms : spec.operation_timeout_ms;
    if (!parse_uint(value, ms) || ms == 0) {
      error =
          std::string(name) + ": milliseconds, a positive whole number (got '" + std::string(value) + "')";
      return false;
    }
    return true;
  }
  if (name == "layout") {
    if (value == "subdirs") return spec.layout = RemoteSpec::Layout::subdirs, true;
    if (value == "flat") return spec.layout = RemoteSpec::Layout::flat, true;
    if (value == "bazel") return spec.layout = RemoteSpec::Layout::bazel, true;
    error = "layout: subdirs, flat or bazel (got '" + std::string(value) + "')";
    return false;
  }
  if (name == "shards") return parse_shards(value, spec.shards, error);
  error = "unknown attribute '" + std::string(attribute) +
          "' (read-only, connect-timeout=MS, operation-timeout=MS, layout=..., shards=...)";
  return false;
}

// A URL's host and port ("host", "host:port", "[v6]:port"), checked.
bool parse_host_port(std::string_view authority, std::string& host, uint32_t& port, std::string& error) {
  if (authority.starts_with('[')) {
    const size_t close = authority.find(']');
    if (close == std::string_view::npos) return error = "unclosed '[' in the host", false;
    host = authority.substr(1, close - 1);
    authority.remove_prefix(close + 1);
    if (!authority.empty() && !authority.starts_with(':')) return error = "junk after the host", false;
  } else {
    host = authority.substr(0, authority.find(':'));
    authority.remove_prefix(host.size());
  }
  if (host.empty()) return error = "no host", false;
  if (authority.starts_with(':') && (!parse_uint(authority.substr(1), port) || port == 0 || port > 65535))
    return error = "the port is not a number from 1 to 65535", false;
  return true;
}

// What an http:// or redis:// URL names after its scheme: [[user:]password@]host[:port][/path].
struct Endpoint {
  std::string user, password, host, path;  // path: after the first '/' (redis: the database)
  uint32_t port = 0;                       // 0: the scheme's default
};
bool parse_endpoint(std::string_view rest, Endpoint& out, std::string& error) {
  std::string_view authority = rest.substr(0, rest.find('/'));
  if (authority.size() < rest.size()) out.path = rest.substr(authority.size() + 1);
  if (const size_t at = authority.rfind('@'); at != std::string_view::npos) {
    const std::string_view credentials = authority.substr(0, at);
    const size_t colon = credentials.find(':');
    if (colon != std::string_view::npos) out.user = credentials.substr(0, colon);
    out.password = colon == std::string_view::npos ? credentials : credentials.substr(colon + 1);
    authority.remove_prefix(at + 1);
  }
  return parse_host_port(authority, out.host, out.port, error);
}

bool check_url(RemoteSpec& spec, std::string& error) {
  std::string_view url = spec.url;
  if (url.starts_with("file:")) {
    spec.kind = RemoteSpec::Kind::file;
    url.remove_prefix(5);
    if (url.starts_with("//")) {  // file://[localhost]/dir
      url.remove_prefix(2);
      const std::string_view host = url.substr(0, url.find('/'));
      if (!host.empty() && host != "localhost")
        return error = "a file: URL names a directory of this machine, not of '" + std::string(host) + "'",
               false;
      url.remove_prefix(host.size());
    }
    if (url.empty()) return error = "file: names no directory", false;
    // Absolute from here on: packs run in different directories (the CMake function's run in each source
    // directory) must all reach the same one.
    std::error_code ec;
    spec.url = "file:" + fs::absolute(fs::path(url), ec).lexically_normal().string();
    return true;
  }
  Endpoint endpoint;
  if (url.starts_with("http://") || url.starts_with("https://")) {
    spec.kind = RemoteSpec::Kind::http;
    return parse_endpoint(url.substr(url.find("//") + 2), endpoint, error);
  }
  if (url.starts_with("redis://")) {
    spec.kind = RemoteSpec::Kind::redis;
    if (!parse_endpoint(url.substr(8), endpoint, error)) return false;
    uint32_t db = 0;
    if (!endpoint.path.empty() && !parse_uint(endpoint.path, db))
      return error = "the database after '/' is not a number", false;
    return true;
  }
  error = "not a remote cache URL (http://, https://, redis:// or file:)";
  return false;
}

}  // namespace

std::string display_url(const std::string& url) {
  const size_t scheme = url.find("://");
  if (scheme == std::string::npos) return url;
  const size_t end = url.find('/', scheme + 3), at = url.rfind('@', end);
  if (at == std::string::npos || at < scheme) return url;
  return url.substr(0, scheme + 3) + "***@" + url.substr(at + 1);  // no password in a log
}

namespace {

// Where an entry lies below a URL or directory.
std::string entry_path(const RemoteSpec& spec, const std::string& name) {
  switch (spec.layout) {
    case RemoteSpec::Layout::flat:
      return name;
    case RemoteSpec::Layout::bazel:
      return "ac/" + name;
    case RemoteSpec::Layout::subdirs:
      break;
  }
  return name.substr(0, 2) + "/" + name.substr(2);
}

std::string without_trailing_slash(std::string text) {
  while (text.size() > 1 && text.back() == '/') text.pop_back();
  return text;
}

// libcurl and hiredis are opened when a pack first talks to a server, not linked: linked, they and the
// 26 libraries they need (TLS, Kerberos, LDAP, ...) were loaded by every pack, a tenth of a warm repack of
// small shaders. Their sonames are the ones the build found (STATEPACK_*_SONAME, set by CMake).
struct CurlApi {
  decltype(&curl_global_init) global_init;
  decltype(&curl_easy_init) easy_init;
  decltype(&curl_easy_cleanup) easy_cleanup;
  CURLcode (*easy_setopt)(CURL*, CURLoption, ...);
  decltype(&curl_easy_perform) easy_perform;
  CURLcode (*easy_getinfo)(CURL*, CURLINFO, ...);
  decltype(&curl_easy_strerror) easy_strerror;
  decltype(&curl_slist_append) slist_append;
};
struct HiredisApi {
  decltype(&redisConnectWithTimeout) connect_with_timeout;
  decltype(&redisSetTimeout) set_timeout;
  decltype(&redisCommand) command;
  decltype(&freeReplyObject) free_reply;
  decltype(&redisFree) free_context;
  decltype(&redisAppendCommand) append_command;
  decltype(&redisBufferWrite) buffer_write;
  decltype(&redisBufferRead) buffer_read;
  decltype(&redisGetReplyFromReader) reply_from_reader;
};

// Opens `soname` and finds every symbol `resolve` asks for; nullptr with `error` set when one is missing.
template <class Api, class Resolve>
const Api* load_library(const char* soname, std::string& error, Resolve resolve) {
  static const std::pair<std::optional<Api>, std::string> loaded =
      [&]() -> std::pair<std::optional<Api>, std::string> {
    void* library = ::dlopen(soname, RTLD_NOW | RTLD_LOCAL);
    if (!library) return {std::nullopt, std::string("cannot load ") + soname + ": " + ::dlerror()};
    Api api{};
    std::string missing;
    auto find = [&](auto& slot, const char* name) {
      slot = reinterpret_cast<std::remove_reference_t<decltype(slot)>>(::dlsym(library, name));
      if (!slot) missing = name;
    };
    resolve(api, find);
    if (!missing.empty()) return {std::nullopt, std::string(soname) + " has no " + missing};
    return {api, ""};
  }();
  if (!loaded.first) error = loaded.second;
  return loaded.first ? &*loaded.first : nullptr;
}

const CurlApi* curl_api(std::string& error) {
  const CurlApi* api = load_library<CurlApi>(STATEPACK_LIBCURL_SONAME, error, [](CurlApi& a, auto find) {
    find(a.global_init, "curl_global_init"), find(a.easy_init, "curl_easy_init");
    find(a.easy_cleanup, "curl_easy_cleanup"), find(a.easy_setopt, "curl_easy_setopt");
    find(a.easy_perform, "curl_easy_perform"), find(a.easy_getinfo, "curl_easy_getinfo");
    find(a.easy_strerror, "curl_easy_strerror"), find(a.slist_append, "curl_slist_append");
  });
  static const bool initialised = api && api->global_init(CURL_GLOBAL_DEFAULT) == CURLE_OK;
  if (api && !initialised) error = "libcurl did not initialise";
  return initialised ? api : nullptr;
}

const HiredisApi* hiredis_api(std::string& error) {
  return load_library<HiredisApi>(STATEPACK_HIREDIS_SONAME, error, [](HiredisApi& a, auto find) {
    find(a.connect_with_timeout, "redisConnectWithTimeout"), find(a.set_timeout, "redisSetTimeout");
    find(a.command, "redisCommand"), find(a.free_reply, "freeReplyObject"), find(a.free_context, "redisFree");
    find(a.append_command, "redisAppendCommand"), find(a.buffer_write, "redisBufferWrite");
    find(a.buffer_read, "redisBufferRead"), find(a.reply_from_reader, "redisGetReplyFromReader");
  });
}

// ---- HTTP (libcurl) ----

class HttpBackend final : public RemoteBackend {
 public:
  HttpBackend(const RemoteSpec& spec, std::string base) : spec_(spec), base_(without_trailing_slash(base)) {
    api_ = curl_api(unusable_);
    if (api_ && !(curl_ = api_->easy_init())) unusable_ = "libcurl: no handle";
    if (!curl_) return;
    // What every request of this handle shares (a handle keeps its options from one request to the next).
    api_->easy_setopt(curl_, CURLOPT_NOSIGNAL, 1L);  // time-outs without SIGALRM: the pack has threads
    api_->easy_setopt(curl_, CURLOPT_CONNECTTIMEOUT_MS, long(spec_.connect_timeout_ms));
    api_->easy_setopt(curl_, CURLOPT_TIMEOUT_MS, long(spec_.operation_timeout_ms));
    api_->easy_setopt(curl_, CURLOPT_FOLLOWLOCATION, 0L);
    api_->easy_setopt(curl_, CURLOPT_PROTOCOLS_STR, "http,https");
    static curl_slist* const headers = api_->slist_append(nullptr, "Expect:");  // no 100-continue wait
    api_->easy_setopt(curl_, CURLOPT_HTTPHEADER, headers);
    api_->easy_setopt(curl_, CURLOPT_WRITEFUNCTION, &HttpBackend::write_to);
  }
  ~HttpBackend() override {
    if (curl_) api_->easy_cleanup(curl_);
  }

  Got get(const std::string& name, uint64_t max_bytes, std::vector<uint8_t>& out,
          std::string& error) override {
    if (!curl_) return error = unusable_, Got::failed;
    Sink sink{&out, max_bytes, false};
    out.clear();
    api_->easy_setopt(curl_, CURLOPT_HTTPGET, 1L);
    const auto [rc, status] = perform(name, sink);
    if (rc == CURLE_OK && status == 200) return Got::hit;
    if (rc == CURLE_OK && status == 404) return Got::miss;
    error = sink.too_large   ? "an answer larger than any entry"
            : rc != CURLE_OK ? api_->easy_strerror(rc)
                             : "HTTP status " + std::to_string(status) + " to GET";
    return Got::failed;
  }

  bool put(const std::string& name, std::span<const uint8_t> bytes, std::string& error) override {
    if (!curl_) return error = unusable_, false;
    Source source{bytes, 0};
    api_->easy_setopt(curl_, CURLOPT_UPLOAD, 1L);
    api_->easy_setopt(curl_, CURLOPT_READFUNCTION, &HttpBackend::read_from);
    api_->easy_setopt(curl_, CURLOPT_READDATA, &source);
    api_->easy_setopt(curl_, CURLOPT_INFILESIZE_LARGE, curl_off_t(bytes.size()));
    std::vector<uint8_t> ignored;  // (the server's words about the PUT)
    Sink sink{&ignored, 1 << 16, false};
    const auto [rc, status] = perform(name, sink);
    api_->easy_setopt(curl_, CURLOPT_UPLOAD, 0L);
    if (rc == CURLE_OK && status >= 200 && status < 300) return true;
    error = rc != CURLE_OK ? api_->easy_strerror(rc) : "HTTP status " + std::to_string(status) + " to PUT";
    return false;
  }

 private:
  struct Sink {
    std::vector<uint8_t>* out;
    uint64_t max_bytes;
    bool too_large;
  };
  struct Source {
    std::span<const uint8_t> bytes;
    size_t at;
  };
  static size_t write_to(char* data, size_t size, size_t count, void* user) {
    auto& sink = *static_cast<Sink*>(user);
    const size_t n = size * count;
    if (sink.out->size() + n > sink.max_bytes) return sink.too_large = true, 0;  // ends the transfer
    sink.out->insert(sink.out->end(), data, data + n);
    return n;
  }
  static size_t read_from(char* to, size_t size, size_t count, void* user) {
    auto& source = *static_cast<Source*>(user);
    const size_t n = std::min(size * count, source.bytes.size() - source.at);
    std::memcpy(to, source.bytes.data() + source.at, n);
    source.at += n;
    return n;
  }
  // One request for `name`'s entry, its answer into `sink`: curl's result and the HTTP status.
  std::pair<CURLcode, long> perform(const std::string& name, Sink& sink) {
    const std::string url = base_ + "/" + entry_path(spec_, name);
    api_->easy_setopt(curl_, CURLOPT_URL, url.c_str());
    api_->easy_setopt(curl_, CURLOPT_WRITEDATA, &sink);
    const CURLcode rc = api_->easy_perform(curl_);
    long status = 0;
    api_->easy_getinfo(curl_, CURLINFO_RESPONSE_CODE, &status);
    return {rc, status};
  }

  RemoteSpec spec_;
  std::string base_;
  const CurlApi* api_ = nullptr;
  CURL* curl_ = nullptr;
  std::string unusable_;  // why there is no handle
};

// ---- Redis (hiredis) ----

class RedisBackend final : public RemoteBackend {
 public:
  RedisBackend(const RemoteSpec& spec, std::string url) : spec_(spec), url_(std::move(url)) {}
  ~RedisBackend() override {
    if (context_) api_->free_context(context_);
  }

  Got get(const std::string& name, uint64_t max_bytes, std::vector<uint8_t>& out,
          std::string& error) override {
    if (!connect(error)) return Got::failed;
    const std::string key = "statepack:" + name;
    auto* reply = bounded_get(key, max_bytes, error);
    if (!reply) return Got::failed;
    Got got = Got::failed;
    if (reply->type == REDIS_REPLY_NIL) {
      got = Got::miss;
    } else if (reply->type == REDIS_REPLY_STRING && uint64_t(reply->len) <= max_bytes) {
      out.assign(reinterpret_cast<const uint8_t*>(reply->str),
                 reinterpret_cast<const uint8_t*>(reply->str) + reply->len);
      got = Got::hit;
    } else {
      error = reply->type == REDIS_REPLY_ERROR ? std::string("Redis: ") + reply->str
                                               : "Redis: an answer to GET that is not an entry";
    }
    api_->free_reply(reply);
    return got;
  }

  bool put(const std::string& name, std::span<const uint8_t> bytes, std::string& error) override {
    if (!connect(error)) return false;
    const std::string key = "statepack:" + name;
    auto* reply = static_cast<redisReply*>(
        api_->command(context_, "SET %b %b", key.data(), key.size(), bytes.data(), bytes.size()));
    if (!reply) return error = failure(), false;
    const bool ok = reply->type == REDIS_REPLY_STATUS;
    if (!ok)
      error = reply->type == REDIS_REPLY_ERROR ? std::string("Redis: ") + reply->str
                                               : "Redis: SET not acknowledged";
    api_->free_reply(reply);
    return ok;
  }

 private:
  // GET, read no further than an entry can be long: hiredis buffers a whole answer before it parses it,
  // so a server that streams without end would otherwise be buffered without end.
  redisReply* bounded_get(const std::string& key, uint64_t max_bytes, std::string& error) {
    if (api_->append_command(context_, "GET %b", key.data(), key.size()) != REDIS_OK)
      return error = failure(), nullptr;
    for (int done = 0; !done;)
      if (api_->buffer_write(context_, &done) != REDIS_OK) return error = failure(), nullptr;
    void* reply = nullptr;
    while (true) {
      if (api_->reply_from_reader(context_, &reply) != REDIS_OK) return error = failure(), nullptr;
      if (reply) return static_cast<redisReply*>(reply);
      if (context_->reader->len > max_bytes + 64) {
        error = "Redis: an answer larger than any entry";
        api_->free_context(context_);  // (the rest of the answer is still on the way)
        context_ = nullptr;
        return nullptr;
      }
      if (api_->buffer_read(context_) != REDIS_OK) return error = failure(), nullptr;
    }
  }
  std::string failure() const {
    return context_ && context_->err ? std::string("Redis: ") + context_->errstr : "Redis: no answer";
  }
  static timeval milliseconds(uint32_t ms) { return {time_t(ms / 1000), suseconds_t(ms % 1000 * 1000)}; }
  // Connects on first use, then authenticates and selects the database the URL names.
  bool connect(std::string& error) {
    if (context_) return true;
    if (!(api_ = hiredis_api(error))) return false;
    Endpoint endpoint;  // (checked by parse_remote_storage)
    std::string ignored;
    parse_endpoint(std::string_view(url_).substr(8), endpoint, ignored);
    const uint32_t port = endpoint.port ? endpoint.port : 6379;
    context_ =
        api_->connect_with_timeout(endpoint.host.c_str(), int(port), milliseconds(spec_.connect_timeout_ms));
    if (!context_ || context_->err) return error = failure(), false;
    api_->set_timeout(context_, milliseconds(spec_.operation_timeout_ms));
    auto command = [&](const char* format, auto... args) {
      auto* reply = static_cast<redisReply*>(api_->command(context_, format, args...));
      const bool ok = reply && reply->type != REDIS_REPLY_ERROR;
      if (!ok) error = reply ? std::string("Redis: ") + reply->str : failure();
      if (reply) api_->free_reply(reply);
      return ok;
    };
    if ((!endpoint.user.empty() || !endpoint.password.empty()) &&
        !(endpoint.user.empty() ? command("AUTH %s", endpoint.password.c_str())
                                : command("AUTH %s %s", endpoint.user.c_str(), endpoint.password.c_str())))
      return false;
    if (!endpoint.path.empty() && !command("SELECT %s", endpoint.path.c_str())) return false;
    return true;
  }

  RemoteSpec spec_;
  std::string url_;
  const HiredisApi* api_ = nullptr;
  redisContext* context_ = nullptr;
};

// ---- a directory (file:) ----

class FileBackend final : public RemoteBackend {
 public:
  FileBackend(const RemoteSpec& spec, std::string url) : spec_(spec) {
    dir_ = fs::path(url.substr(5));  // (made absolute by parse_remote_storage)
  }

  Got get(const std::string& name, uint64_t max_bytes, std::vector<uint8_t>& out,
          std::string& error) override {
    const fs::path path = dir_ / entry_path(spec_, name);
    switch (read_entry_file(path, max_bytes, out)) {
      case EntryRead::ok:
        return Got::hit;
      case EntryRead::missing:
        return Got::miss;
      case EntryRead::unusable:
        break;
    }
    error = "'" + printable(path.string()) +
            "' cannot be read as an entry (a link, not a regular file, too large)";
    return Got::failed;
  }

  bool put(const std::string& name, std::span<const uint8_t> bytes, std::string& error) override {
    const fs::path path = dir_ / entry_path(spec_, name);
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    return write_beside_and_rename(path, bytes, error);
  }

 private:
  RemoteSpec spec_;
  fs::path dir_;
};

std::unique_ptr<RemoteBackend> make_backend(const RemoteSpec& spec, std::string url) {
  switch (spec.kind) {
    case RemoteSpec::Kind::http:
      return std::make_unique<HttpBackend>(spec, std::move(url));
    case RemoteSpec::Kind::redis:
      return std::make_unique<RedisBackend>(spec, std::move(url));
    case RemoteSpec::Kind::file:
      return std::make_unique<FileBackend>(spec, std::move(url));
  }
  return nullptr;
}

}  // namespace

std::optional<std::vector<RemoteSpec>> parse_remote_storage(std::string_view text, std::string& error) {
  std::vector<RemoteSpec> specs;
  while (true) {
    const size_t start = text.find_first_not_of(" \t\n");
    if (start == std::string_view::npos) break;
    text.remove_prefix(start);
    const std::string_view item = text.substr(0, text.find_first_of(" \t\n"));
    text.remove_prefix(item.size());
    RemoteSpec spec;
    std::string_view rest = item;
    spec.url = rest.substr(0, rest.find('|'));
    rest.remove_prefix(spec.url.size());
    std::string why;
    bool ok = check_url(spec, why);
    while (ok && !rest.empty()) {
      rest.remove_prefix(1);
      const std::string_view attribute = rest.substr(0, rest.find('|'));
      rest.remove_prefix(attribute.size());
      ok = parse_attribute(attribute, spec, why);
    }
    const bool starred = spec.url.find('*') != std::string::npos;
    if (ok && starred != !spec.shards.empty()) {
      why = starred ? "'*' in the URL needs shards=..."
                    : "shards=... needs a '*' in the URL for the shard's name";
      ok = false;
    }
    if (!ok) {
      error = "'" + printable(display_url(std::string(item))) + "': " + why;  // (no password in a log)
      return std::nullopt;
    }
    specs.push_back(std::move(spec));
  }
  if (specs.empty()) {
    error = "no remote cache URL given";
    return std::nullopt;
  }
  return specs;
}

// One server: its connections (one backend per shard each; idle ones kept for the next request, so that
// the pack's threads talk to it at once), whether it failed (then left alone), its counts.
struct RemoteCache::Server {
  using Connection = std::vector<std::unique_ptr<RemoteBackend>>;
  RemoteSpec spec;
  std::mutex mutex;  // everything below
  std::vector<std::unique_ptr<Connection>> idle;
  bool read_failed = false, write_failed = false;
  size_t failures = 0, skipped = 0;  // requests that failed; requests not sent after a failure
  std::string first_failure;

  // An idle connection, or a new one. Under `mutex`.
  std::unique_ptr<Connection> take() {
    if (!idle.empty()) {
      auto c = std::move(idle.back());
      idle.pop_back();
      return c;
    }
    auto c = std::make_unique<Connection>();
    if (spec.shards.empty()) c->push_back(make_backend(spec, spec.url));
    for (const auto& shard : spec.shards) {
      std::string url = spec.url;
      url.replace(url.find('*'), 1, shard.name);
      c->push_back(make_backend(spec, url));
    }
    return c;
  }
  // The shard an entry's name goes to: rendezvous hashing (each name scores every shard; the highest
  // weighted score wins, so adding a shard moves only the entries it wins).
  size_t shard_of(const std::string& name) const {
    size_t best = 0;
    double best_score = -1;
    for (size_t i = 0; i < spec.shards.size(); ++i) {
      const Digest d = sha256(spec.shards[i].name + "\n" + name);
      uint64_t h = 0;
      for (int b = 0; b < 8; ++b) h = h << 8 | d[size_t(b)];
      // Weighted rendezvous hashing: weight / -ln(u) for u uniform in (0, 1) gives each shard its share.
      const double u = (double(h >> 11) + 0.5) / double(uint64_t(1) << 53);
      const double score = spec.shards[i].weight / -std::log(u);
      if (score > best_score) best_score = score, best = i;
    }
    return best;
  }
  // Sends one request, `request(backend, error)` (true: the server answered), on a connection of its own
  // unless the server failed before (for reading, or for writing); nullopt when it was not sent. After it,
  // the connection is kept for the next request, or, when it failed, the server is left alone for reading
  // and writing (`reading`) or for writing.
  template <class Request>
  std::optional<bool> send(const std::string& name, bool reading, Request request) {
    std::unique_ptr<Connection> connection;
    {
      std::lock_guard lock(mutex);
      if (reading ? read_failed : write_failed) return ++skipped, std::nullopt;
      connection = take();
    }
    std::string error;
    const bool ok = request(*(*connection)[shard_of(name)], error);
    std::lock_guard lock(mutex);
    if (ok) {
      idle.push_back(std::move(connection));
      return true;
    }
    write_failed = true;
    read_failed = read_failed || reading;  // (a server may refuse writes and still serve)
    if (failures++ == 0) first_failure = error;
    return false;
  }
};

RemoteCache::RemoteCache(std::vector<RemoteSpec> specs) {
  for (auto& spec : specs) {
    servers_.push_back(std::make_unique<Server>());
    servers_.back()->spec = std::move(spec);
  }
}
RemoteCache::~RemoteCache() = default;

std::optional<std::vector<uint8_t>> RemoteCache::get(const std::string& name, uint64_t max_bytes) {
  for (auto& server : servers_) {
    std::vector<uint8_t> bytes;
    RemoteBackend::Got got = RemoteBackend::Got::miss;
    const std::optional<bool> answered =
        server->send(name, true, [&](RemoteBackend& backend, std::string& error) {
          got = backend.get(name, max_bytes, bytes, error);
          return got != RemoteBackend::Got::failed;
        });
    if (!answered) continue;
    std::lock_guard lock(mutex_);
    if (!*answered) {
      ++stats_.errors;
    } else if (got == RemoteBackend::Got::hit) {
      ++stats_.hits;
      stats_.bytes_read += bytes.size();
      return bytes;
    }
  }
  std::lock_guard lock(mutex_);
  ++stats_.misses;
  return std::nullopt;
}

void RemoteCache::put(const std::string& name, std::span<const uint8_t> bytes) {
  for (auto& server : servers_) {
    if (server->spec.read_only) continue;
    const std::optional<bool> answered = server->send(
        name, false,
        [&](RemoteBackend& backend, std::string& error) { return backend.put(name, bytes, error); });
    if (!answered) continue;
    std::lock_guard lock(mutex_);
    if (*answered) {
      ++stats_.written;
      stats_.bytes_written += bytes.size();
    } else {
      ++stats_.errors;
    }
  }
}

void RemoteCache::put_all(const std::vector<std::pair<std::string, std::vector<uint8_t>>>& entries) {
  // A few requests in flight at once: a write waits on the network, not on this machine's cores.
  detail::parallel_for(entries.size(), kConnections,
                       [&](size_t i) { put(entries[i].first, entries[i].second); });
}

RemoteCache::Stats RemoteCache::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

std::string RemoteCache::warning() const {
  std::string text;
  for (const auto& server : servers_) {
    if (!server->failures) continue;
    if (!text.empty()) text += "\n";
    text +=
        "remote cache '" + printable(display_url(server->spec.url)) +
        "': " + printable(server->first_failure) +
        (server->read_failed ? "; not asked again in this pack (" : "; not written again in this pack (") +
        std::to_string(server->skipped) + " requests not sent)";
  }
  return text;
}

}  // namespace statepack::packager
