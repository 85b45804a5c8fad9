// statepack pack --remote-cache: the compile cache's entries on servers a team already runs, behind the
// local --cache-dir. The syntax is ccache's remote_storage: one or more servers separated by spaces, each
// a URL followed by attributes after '|':
//
//   http://host[:port]/path      GET/PUT of entries (nginx with WebDAV PUT, any ccache HTTP server)
//   redis://[[user:]password@]host[:port][/db]   GET/SET of "statepack:<key>"
//   file:DIR                     a directory on a shared file system, written atomically
//
// | attribute             | meaning                                                                  |
// |-----------------------|--------------------------------------------------------------------------|
// | read-only             | never written (a CI job that only reads)                                 |
// | connect-timeout=MS    | connecting at most this long (default 100)                               |
// | operation-timeout=MS  | one request at most this long (default 10000)                            |
// | layout=subdirs        | http and file: where an entry lies: subdirs (default) "ab/cdef...",      |
// |   flat, bazel         |   flat "abcdef...", bazel "ac/abcdef..." (a Bazel remote cache's layout) |
// | shards=A,B(2),...     | the URL holds '*': each entry goes to one of these (rendezvous hashing,  |
// |                       |   weighted), so a cache can be spread over several servers              |
//
// Entries are found by name (the key in hex); what comes back is checked by the compile cache (header,
// key, payload hash, signature) before use. Each thread of the pack has a connection of its own to a
// server (kept open between requests). A server never fails a pack: the first failure (refused
// connection, time-out, an HTTP status other than found/not found, a Redis error) leaves that server
// alone for the rest of the pack (requests already in flight on other connections end as they end),
// counted, and reported once as a warning.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace statepack::packager {

struct RemoteSpec {
  enum class Kind { http, redis, file };
  std::string url;  // as given (with '*' where a shard's name goes)
  Kind kind = Kind::http;
  bool read_only = false;
  uint32_t connect_timeout_ms = 100, operation_timeout_ms = 10000;
  enum class Layout { subdirs, flat, bazel };
  Layout layout = Layout::subdirs;
  struct Shard {
    std::string name;
    double weight = 1;
  };
  std::vector<Shard> shards;
};

// Parses ccache's remote_storage syntax; nullopt with `error` saying what is wrong.
std::optional<std::vector<RemoteSpec>> parse_remote_storage(std::string_view text, std::string& error);

// A URL as messages show it: a password in it replaced by ***.
std::string display_url(const std::string& url);

// One server (or one shard of it), as the remote cache talks to it.
class RemoteBackend {
 public:
  virtual ~RemoteBackend() = default;
  enum class Got { hit, miss, failed };
  // An entry's bytes (at most `max_bytes`), a miss, or a failure with `error` set.
  virtual Got get(const std::string& name, uint64_t max_bytes, std::vector<uint8_t>& out,
                  std::string& error) = 0;
  virtual bool put(const std::string& name, std::span<const uint8_t> bytes, std::string& error) = 0;
};

class RemoteCache {
 public:
  explicit RemoteCache(std::vector<RemoteSpec> specs);
  ~RemoteCache();

  // An entry from the first server that has it; nullopt when none does (or each failed). Thread-safe.
  std::optional<std::vector<uint8_t>> get(const std::string& name, uint64_t max_bytes);
  // Writes an entry to every server that is not read-only and has not failed. Thread-safe.
  void put(const std::string& name, std::span<const uint8_t> bytes);
  // put() for each entry, kConnections at once.
  static constexpr uint32_t kConnections = 4;
  void put_all(const std::vector<std::pair<std::string, std::vector<uint8_t>>>& entries);

  struct Stats {
    size_t hits = 0, misses = 0, errors = 0, written = 0;
    uint64_t bytes_read = 0, bytes_written = 0;
  };
  Stats stats() const;
  // One line per server that failed: what failed first and how many requests failed; "" when none.
  std::string warning() const;

 private:
  struct Server;
  std::vector<std::unique_ptr<Server>> servers_;
  mutable std::mutex mutex_;  // stats_
  Stats stats_;
};

}  // namespace statepack::packager
