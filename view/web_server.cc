#include "view/web_server.h"

#include <civetweb.h>

#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "log/log.h"

namespace dt {
namespace {

const char* MimeOf(const std::filesystem::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".png") return "image/png";
  return "application/octet-stream";
}

}  // namespace

WebServer::WebServer(const std::string& address, int port, std::filesystem::path web_dir,
                     Handlers handlers)
    : web_dir_(std::move(web_dir)), handlers_(std::move(handlers)) {
  mg_init_library(MG_FEATURES_WEBSOCKET);
  const std::string ports = fmt::format("{}:{}", address, port);
  const char* options[] = {"listening_ports",      ports.c_str(), "num_threads", "16",
                           "websocket_timeout_ms", "3600000",     nullptr};
  mg_callbacks callbacks{};
  ctx_ = mg_start(&callbacks, this, options);
  if (ctx_ == nullptr) {
    throw std::runtime_error(fmt::format(
        "the view cannot listen on {} (in use, or not an address of this host)", ports));
  }
  mg_set_request_handler(ctx_, "/relief.png", &WebServer::HandleRelief, this);
  if (handlers_.relief_tile)
    mg_set_request_handler(ctx_, "/relief/", &WebServer::HandleReliefTile, this);
  if (handlers_.terrain3d)
    mg_set_request_handler(ctx_, "/terrain3d", &WebServer::HandleTerrain3d, this);
  mg_set_websocket_handler(ctx_, "/ws", &WebServer::WsConnect, &WebServer::WsReady,
                           &WebServer::WsData, &WebServer::WsClose, this);
  mg_set_request_handler(ctx_, "/", &WebServer::HandleFile, this);
}

WebServer::~WebServer() {
  if (ctx_ != nullptr) mg_stop(ctx_);
}

int WebServer::HandleFile(mg_connection* conn, void* self_ptr) {
  auto* self = static_cast<WebServer*>(self_ptr);
  std::string uri = mg_get_request_info(conn)->local_uri;
  if (uri == "/") uri = "/index.html";
  // The page's own files only: one path component, no way out of web_dir.
  const std::string name = uri.substr(1);
  if (name.empty() || name.find('/') != std::string::npos || name.find("..") != std::string::npos) {
    mg_send_http_error(conn, 404, "%s", "not found");
    return 404;
  }
  const std::filesystem::path path = self->web_dir_ / name;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    mg_send_http_error(conn, 404, "%s", "not found");
    return 404;
  }
  mg_send_mime_file(conn, path.c_str(), MimeOf(path));
  return 200;
}

int WebServer::HandleRelief(mg_connection* conn, void* self_ptr) {
  auto* self = static_cast<WebServer*>(self_ptr);
  if (self->handlers_.relief_tile) return HandleReliefTile(conn, self_ptr);
  std::string png;
  {
    std::lock_guard lock(self->relief_mu_);
    png = self->relief_;
  }
  if (png.empty()) {
    mg_send_http_error(conn, 503, "%s", "the relief is not rendered yet");
    return 503;
  }
  mg_send_http_ok(conn, "image/png", static_cast<long long>(png.size()));
  mg_write(conn, png.data(), png.size());
  return 200;
}

int WebServer::HandleTerrain3d(mg_connection* conn, void* self_ptr) {
  auto* self = static_cast<WebServer*>(self_ptr);
  const char* query = mg_get_request_info(conn)->query_string;
  const auto [status, body] = self->handlers_.terrain3d(query == nullptr ? "" : query);
  if (status != 200) {
    mg_send_http_error(conn, status, "%s", body.c_str());
    return status;
  }
  mg_send_http_ok(conn, "application/json", static_cast<long long>(body.size()));
  mg_write(conn, body.data(), body.size());
  return 200;
}

int WebServer::HandleReliefTile(mg_connection* conn, void* self_ptr) {
  auto* self = static_cast<WebServer*>(self_ptr);
  const std::string uri = mg_get_request_info(conn)->local_uri;
  const std::string prefix = "/relief/";
  const std::string tile = uri.starts_with(prefix) ? uri.substr(prefix.size()) : "0/0/0";
  const auto [status, body] = self->handlers_.relief_tile(tile);
  if (status != 200) {
    mg_send_http_error(conn, status, "%s", body.c_str());
    return status;
  }
  // A URL naming the tile's version (?v=, as the page asks) stays right and may be kept.
  const char* query = mg_get_request_info(conn)->query_string;
  const bool versioned = query != nullptr && std::strstr(query, "v=") != nullptr;
  mg_printf(conn,
            "HTTP/1.1 200 OK\r\nContent-Type: image/png\r\nContent-Length: %zu\r\n"
            "Cache-Control: %s\r\n\r\n",
            body.size(), versioned ? "private, max-age=3600" : "no-cache");
  mg_write(conn, body.data(), body.size());
  return 200;
}

void WebServer::Write(mg_connection* conn, const Message& m) {
  mg_websocket_write(conn, m.binary ? MG_WEBSOCKET_OPCODE_BINARY : MG_WEBSOCKET_OPCODE_TEXT,
                     m.data.data(), m.data.size());
}

int WebServer::WsConnect(const mg_connection*, void*) { return 0; }  // every page is accepted

void WebServer::WsReady(mg_connection* conn, void* self_ptr) {
  auto* self = static_cast<WebServer*>(self_ptr);
  std::function<std::string()> write;
  {
    std::lock_guard lock(self->mu_);
    write = self->handlers_.snapshot();
    self->opening_[conn];
  }
  // civetweb calls this page's close handler on this thread, after this returns: the connection
  // stays valid while the snapshot is written.
  const std::string snapshot = write();
  mg_websocket_write(conn, MG_WEBSOCKET_OPCODE_TEXT, snapshot.data(), snapshot.size());
  std::lock_guard lock(self->mu_);
  for (const Message& m : self->opening_[conn]) Write(conn, m);
  self->opening_.erase(conn);
  self->pages_.insert(conn);
}

int WebServer::WsData(mg_connection* conn, int flags, char* data, size_t len, void* self_ptr) {
  auto* self = static_cast<WebServer*>(self_ptr);
  const int opcode = flags & 0xf;
  if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
  if (opcode != MG_WEBSOCKET_OPCODE_TEXT) return 1;  // pings and binary frames: nothing to do
  const std::string reply = self->handlers_.message(std::string(data, len));
  if (!reply.empty())
    mg_websocket_write(conn, MG_WEBSOCKET_OPCODE_TEXT, reply.data(), reply.size());
  return 1;
}

void WebServer::WsClose(const mg_connection* conn, void* self_ptr) {
  auto* self = static_cast<WebServer*>(self_ptr);
  std::lock_guard lock(self->mu_);
  self->pages_.erase(const_cast<mg_connection*>(conn));
  self->opening_.erase(const_cast<mg_connection*>(conn));
}

void WebServer::Publish(const std::function<std::vector<Message>()>& make) {
  std::lock_guard lock(mu_);
  for (Message& m : make()) {
    if (m.data.empty()) continue;
    for (mg_connection* c : pages_) Write(c, m);
    for (auto& [c, waiting] : opening_) waiting.push_back(m);
  }
}

void WebServer::SetRelief(std::string png_bytes) {
  std::lock_guard lock(relief_mu_);
  relief_ = std::move(png_bytes);
}

size_t WebServer::pages() const {
  std::lock_guard lock(mu_);
  return pages_.size();
}

}  // namespace dt
