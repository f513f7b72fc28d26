// WebServer: the live view's HTTP and WebSocket endpoint over civetweb: the page's files, the
// relief image, the 3D view's terrain windows, and one WebSocket per page that gets a snapshot,
// then every delta.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <utility>
#include <vector>

struct mg_context;
struct mg_connection;

namespace dt {

class WebServer {
 public:
  // One WebSocket message: text (JSON) or binary (docs/view.md "The binary vehicle message").
  struct Message {
    std::string data;
    bool binary = false;
  };
  struct Handlers {
    // The snapshot a page that just connected receives, in two steps: `snapshot` is called under
    // the publish lock and copies what the page needs (quickly: the view's loop waits for it);
    // the function it returns writes the message from that copy on the page's own thread, the
    // lock released. Deltas published meanwhile wait for the page and follow its snapshot, so a
    // page misses none and sees none twice.
    std::function<std::function<std::string()>()> snapshot;
    // A message from a page (an operator command); the reply sent back to that page alone.
    // Called on a civetweb thread.
    std::function<std::string(const std::string& message)> message;
    // GET /terrain3d?<query>: the HTTP status and the JSON body. Called on a civetweb thread;
    // absent, the path is not found.
    std::function<std::pair<int, std::string>(const std::string& query)> terrain3d;
    // GET /relief/<level>/<x>/<z>.png: the HTTP status and the PNG (or, not 200, why). Called on
    // a civetweb thread; present, /relief.png is its tile 0/0/0.
    std::function<std::pair<int, std::string>(const std::string& tile)> relief_tile;
  };

  // Serves `web_dir`'s files (index.html at /) on address:port. Throws std::runtime_error naming
  // the address and port when it cannot listen.
  WebServer(const std::string& address, int port, std::filesystem::path web_dir, Handlers handlers);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  // Under the publish lock: `make` builds the tick's messages (it may update what snapshot()
  // reads); each non-empty one goes to every page, in order.
  void Publish(const std::function<std::vector<Message>()>& make);
  // The relief image served at /relief.png.
  void SetRelief(std::string png_bytes);
  size_t pages() const;

 private:
  static void Write(mg_connection* conn, const Message& m);
  static int HandleFile(mg_connection* conn, void* self);
  static int HandleRelief(mg_connection* conn, void* self);
  static int HandleTerrain3d(mg_connection* conn, void* self);
  static int HandleReliefTile(mg_connection* conn, void* self);
  static int WsConnect(const mg_connection* conn, void* self);
  static void WsReady(mg_connection* conn, void* self);
  static int WsData(mg_connection* conn, int flags, char* data, size_t len, void* self);
  static void WsClose(const mg_connection* conn, void* self);

  std::filesystem::path web_dir_;
  Handlers handlers_;
  mutable std::mutex mu_;  // pages_ and everything Publish's and snapshot's callbacks touch
  std::set<mg_connection*> pages_;
  // Pages whose snapshot is being written, and the deltas published since their copy.
  std::map<mg_connection*, std::vector<Message>> opening_;
  std::mutex relief_mu_;
  std::string relief_;
  mg_context* ctx_ = nullptr;
};

}  // namespace dt
