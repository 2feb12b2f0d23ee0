#include "bridge_server.hpp"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

namespace ucon {
namespace foxglove {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

namespace {
class ClientConnection;
}  // namespace

class BridgeServer::Impl {
 public:
  explicit Impl(const Options& o) : options(o), acceptor(ioc) {}

  void accept();
  void addClient(const std::shared_ptr<ClientConnection>& s);
  void removeClient(ClientConnection* s);
  void subscriptionsChanged(const std::vector<uint32_t>& added, const std::vector<uint32_t>& removed);

  Options options;
  net::io_context ioc;
  tcp::acceptor acceptor;
  std::thread thread;
  std::atomic<bool> stopping{false};
  std::string instance_id;

  mutable std::mutex mutex;  // guards everything below
  std::map<uint32_t, WsChannel> channels;
  std::map<ClientConnection*, std::shared_ptr<ClientConnection>> open_clients;
  std::map<uint32_t, int> subscribers;  // channel id -> clients subscribed
  std::vector<uint32_t> new_subscriptions;
  Stats stats;
};

namespace {

// One WebSocket client. Its socket is used on the I/O thread only; its queues are filled from
// the LCM thread under `mutex_`.
class ClientConnection : public std::enable_shared_from_this<ClientConnection> {
 public:
  ClientConnection(tcp::socket socket, BridgeServer::Impl* server)
      : ex_(socket.get_executor()),
        stream_(std::move(socket)),
        server_(server),
        data_(server->options.queue_messages, server->options.queue_bytes) {}

  void start() {
    stream_.expires_after(std::chrono::seconds(10));
    http::async_read(stream_, buffer_, request_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) { self->onRequest(ec); });
  }

  // Queues a frame that must arrive (serverInfo, advertise, status, time).
  void sendControl(OutFrame f) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      control_.push_back(std::move(f));
    }
    kick();
  }

  // Queues a message for subscription of `channel_id`; false when not subscribed.
  bool sendData(uint32_t channel_id, uint64_t ns, const std::shared_ptr<const std::string>& payload,
                std::size_t* dropped) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto sub = subs_.subscriptionFor(channel_id);
      if (!sub) return false;
      OutFrame f;
      f.head = messageDataHeader(*sub, ns);
      f.payload = payload;
      *dropped = data_.push(std::move(f));
    }
    kick();
    return true;
  }

  // Queues a frame that may be dropped like data when the client is slow (Time messages).
  void sendDroppable(OutFrame f, std::size_t* dropped) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      *dropped = data_.push(std::move(f));
    }
    kick();
  }

  void close() {
    net::post(ex_, [self = shared_from_this()] {
      if (self->ws_ && self->ws_->is_open()) {
        self->ws_->async_close(websocket::close_code::going_away, [self](beast::error_code) { self->finish(); });
      } else {
        beast::error_code ec;
        beast::get_lowest_layer(self->stream()).socket().close(ec);
        self->finish();
      }
    });
  }

 private:
  beast::tcp_stream& stream() { return ws_ ? beast::get_lowest_layer(*ws_) : stream_; }

  void refuseHttp(http::status status, const std::string& body) {
    {
      std::lock_guard<std::mutex> lock(server_->mutex);
      ++server_->stats.rejected;
    }
    auto res = std::make_shared<http::response<http::string_body>>(status, request_.version());
    res->set(http::field::server, server_->options.name);
    res->set(http::field::content_type, "text/plain");
    res->keep_alive(false);
    res->body() = body + "\n";
    res->prepare_payload();
    http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code, std::size_t) {
      beast::error_code ec;
      self->stream_.socket().shutdown(tcp::socket::shutdown_both, ec);
    });
  }

  void onRequest(beast::error_code ec) {
    if (ec) return;  // not even an HTTP request: drop the connection
    if (!websocket::is_upgrade(request_)) {
      refuseHttp(http::status::upgrade_required,
                 "ucon-foxglove-bridge speaks the Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1): "
                 "open it from Foxglove, 'Open connection' -> 'Foxglove WebSocket'");
      return;
    }
    if (!offersSubprotocol(std::string(request_[http::field::sec_websocket_protocol]))) {
      refuseHttp(http::status::bad_request, "this server needs the WebSocket subprotocol foxglove.websocket.v1");
      return;
    }
    bool full = false;
    {
      std::lock_guard<std::mutex> lock(server_->mutex);
      full = static_cast<int>(server_->open_clients.size()) >= server_->options.max_clients;
    }
    if (full) {
      refuseHttp(http::status::service_unavailable,
                 "too many clients (" + std::to_string(server_->options.max_clients) + "; --max-clients)");
      return;
    }
    stream_.expires_never();
    ws_.emplace(std::move(stream_));
    ws_->set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    const std::string name = server_->options.name;
    ws_->set_option(websocket::stream_base::decorator([name](websocket::response_type& res) {
      res.set(http::field::sec_websocket_protocol, kSubprotocol);
      res.set(http::field::server, name);
    }));
    ws_->read_message_max(1u << 20);  // clients send small requests only
    ws_->async_accept(request_, [self = shared_from_this()](beast::error_code e) { self->onAccept(e); });
  }

  void onAccept(beast::error_code ec) {
    if (ec) return;
    server_->addClient(shared_from_this());
    doRead();
  }

  void doRead() {
    ws_->async_read(in_, [self = shared_from_this()](beast::error_code ec, std::size_t) { self->onRead(ec); });
  }

  void status(StatusLevel level, const std::string& message) {
    OutFrame f;
    f.text = true;
    f.head = statusJson(level, message);
    sendControl(std::move(f));
  }

  void onRead(beast::error_code ec) {
    if (ec) {
      finish();
      return;
    }
    const std::string text = beast::buffers_to_string(in_.data());
    in_.consume(in_.size());
    if (!ws_->got_text()) {
      status(StatusLevel::kError, refuseClientBinary(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
      countRefused();
      doRead();
      return;
    }
    const ClientRequest req = parseClientText(text);
    std::vector<std::string> errors;
    std::vector<uint32_t> added, removed;
    switch (req.kind) {
      case ClientRequest::Kind::kSubscribe: {
        std::map<uint32_t, WsChannel> channels;
        {
          std::lock_guard<std::mutex> lock(server_->mutex);
          channels = server_->channels;
        }
        std::lock_guard<std::mutex> lock(mutex_);
        errors = subs_.subscribe(req.subscribe, channels, &added);
        break;
      }
      case ClientRequest::Kind::kUnsubscribe: {
        std::lock_guard<std::mutex> lock(mutex_);
        errors = subs_.unsubscribe(req.unsubscribe, &removed);
        break;
      }
      case ClientRequest::Kind::kRefused:
        countRefused();
        errors.push_back(req.error);
        break;
      case ClientRequest::Kind::kInvalid:
        errors.push_back("invalid request: " + req.error);
        break;
    }
    if (!added.empty() || !removed.empty()) server_->subscriptionsChanged(added, removed);
    for (const auto& e : errors) status(StatusLevel::kError, e);
    doRead();
  }

  void countRefused() {
    std::lock_guard<std::mutex> lock(server_->mutex);
    ++server_->stats.refused_requests;
  }

  void kick() {
    if (write_posted_.exchange(true)) return;
    net::post(ex_, [self = shared_from_this()] {
      self->write_posted_ = false;
      self->doWrite();
    });
  }

  void doWrite() {
    if (writing_ || !ws_ || !ws_->is_open() || finished_) return;
    std::optional<OutFrame> f;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!control_.empty()) {
        f = std::move(control_.front());
        control_.pop_front();
      } else {
        f = data_.pop();
      }
    }
    if (!f) return;
    writing_ = true;
    current_ = std::move(*f);
    ws_->text(current_.text);
    std::array<net::const_buffer, 2> buffers = {
        net::buffer(current_.head),
        current_.payload ? net::buffer(*current_.payload) : net::const_buffer()};
    ws_->async_write(buffers, [self = shared_from_this()](beast::error_code ec, std::size_t n) {
      self->writing_ = false;
      if (ec) {
        self->finish();
        return;
      }
      {
        std::lock_guard<std::mutex> lock(self->server_->mutex);
        ++self->server_->stats.frames_sent;
        self->server_->stats.bytes_sent += n;
      }
      self->current_ = OutFrame();
      self->doWrite();
    });
  }

  // The connection is over (closed, failed): unregister it once.
  void finish() {
    if (finished_) return;
    finished_ = true;
    std::vector<uint32_t> removed;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      removed = subs_.channels();
    }
    server_->subscriptionsChanged({}, removed);
    server_->removeClient(this);
  }

  net::any_io_executor ex_;  // the I/O thread's, for work posted from the LCM thread
  beast::tcp_stream stream_;
  std::optional<websocket::stream<beast::tcp_stream>> ws_;
  BridgeServer::Impl* server_;
  beast::flat_buffer buffer_, in_;
  http::request<http::string_body> request_;

  mutable std::mutex mutex_;  // guards subs_, control_, data_
  ClientSubscriptions subs_;
  std::deque<OutFrame> control_;
  DropOldestQueue data_;

  std::atomic<bool> write_posted_{false};
  bool writing_ = false;  // I/O thread only
  bool finished_ = false;
  OutFrame current_;
};

}  // namespace

void BridgeServer::Impl::accept() {
  acceptor.async_accept(ioc, [this](beast::error_code ec, tcp::socket socket) {
    if (stopping) return;
    if (!ec) {
      beast::error_code ignored;
      socket.set_option(tcp::no_delay(true), ignored);
      std::make_shared<ClientConnection>(std::move(socket), this)->start();
    }
    accept();
  });
}

void BridgeServer::Impl::addClient(const std::shared_ptr<ClientConnection>& s) {
  std::vector<WsChannel> list;
  {
    std::lock_guard<std::mutex> lock(mutex);
    open_clients[s.get()] = s;
    ++stats.connections;
    for (const auto& [id, c] : channels) list.push_back(c);
  }
  OutFrame info;
  info.text = true;
  info.head = serverInfoJson(options.name, instance_id);
  s->sendControl(std::move(info));
  OutFrame adv;
  adv.text = true;
  adv.head = advertiseJson(list);
  s->sendControl(std::move(adv));
  if (stopping) s->close();
}

void BridgeServer::Impl::removeClient(ClientConnection* s) {
  std::lock_guard<std::mutex> lock(mutex);
  open_clients.erase(s);
}

void BridgeServer::Impl::subscriptionsChanged(const std::vector<uint32_t>& added,
                                              const std::vector<uint32_t>& removed) {
  std::lock_guard<std::mutex> lock(mutex);
  for (uint32_t c : added) {
    ++subscribers[c];
    new_subscriptions.push_back(c);
  }
  for (uint32_t c : removed) {
    if (--subscribers[c] <= 0) subscribers.erase(c);
  }
}

BridgeServer::BridgeServer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

BridgeServer::~BridgeServer() { stop(); }

std::unique_ptr<BridgeServer> BridgeServer::start(const Options& options, const std::vector<WsChannel>& channels,
                                                  std::string* error) {
  auto impl = std::make_unique<Impl>(options);
  beast::error_code ec;
  const auto address = net::ip::make_address(options.bind, ec);
  if (ec) {
    *error = "'" + options.bind + "' is not an IP address (--bind)";
    return nullptr;
  }
  const tcp::endpoint endpoint(address, options.port);
  const std::string where = options.bind + ":" + std::to_string(options.port);
  impl->acceptor.open(endpoint.protocol(), ec);
  if (!ec) impl->acceptor.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) impl->acceptor.bind(endpoint, ec);
  if (!ec) impl->acceptor.listen(net::socket_base::max_listen_connections, ec);
  if (ec) {
    *error = "cannot listen on " + where + ": " + ec.message();
    return nullptr;
  }
  impl->instance_id = std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(
                                        std::chrono::system_clock::now().time_since_epoch())
                                        .count());
  for (const auto& c : channels) impl->channels[c.id] = c;
  impl->accept();
  Impl* raw = impl.get();
  impl->thread = std::thread([raw] { raw->ioc.run(); });
  return std::unique_ptr<BridgeServer>(new BridgeServer(std::move(impl)));
}

uint16_t BridgeServer::port() const {
  beast::error_code ec;
  const auto ep = impl_->acceptor.local_endpoint(ec);
  return ec ? impl_->options.port : ep.port();
}

void BridgeServer::advertise(const std::vector<WsChannel>& channels) {
  if (channels.empty()) return;
  std::vector<std::shared_ptr<ClientConnection>> open_clients;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    for (const auto& c : channels) impl_->channels[c.id] = c;
    for (const auto& [p, s] : impl_->open_clients) open_clients.push_back(s);
  }
  const std::string text = advertiseJson(channels);
  for (const auto& s : open_clients) {
    OutFrame f;
    f.text = true;
    f.head = text;
    s->sendControl(std::move(f));
  }
}

bool BridgeServer::wanted(uint32_t channel_id) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->subscribers.count(channel_id) > 0;
}

void BridgeServer::publish(const std::vector<BridgeOutput>& outputs) {
  if (outputs.empty()) return;
  std::vector<std::shared_ptr<ClientConnection>> open_clients;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    for (const auto& [p, s] : impl_->open_clients) open_clients.push_back(s);
  }
  std::size_t dropped = 0;
  for (const auto& o : outputs) {
    for (const auto& s : open_clients) {
      std::size_t d = 0;
      if (s->sendData(o.channel_id, o.timestamp_ns, o.payload, &d)) dropped += d;
    }
  }
  if (dropped > 0) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stats.dropped += dropped;
  }
}

void BridgeServer::broadcastTime(uint64_t timestamp_ns) {
  std::vector<std::shared_ptr<ClientConnection>> open_clients;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    for (const auto& [p, s] : impl_->open_clients) open_clients.push_back(s);
  }
  std::size_t dropped = 0;
  for (const auto& s : open_clients) {
    OutFrame f;
    f.head = timeMessage(timestamp_ns);
    std::size_t d = 0;
    s->sendDroppable(std::move(f), &d);
    dropped += d;
  }
  if (dropped > 0) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stats.dropped += dropped;
  }
}

std::vector<uint32_t> BridgeServer::takeNewSubscriptions() {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  std::vector<uint32_t> out;
  out.swap(impl_->new_subscriptions);
  return out;
}

BridgeServer::Stats BridgeServer::stats() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  Stats s = impl_->stats;
  s.clients = static_cast<int>(impl_->open_clients.size());
  return s;
}

void BridgeServer::stop() {
  if (!impl_ || !impl_->thread.joinable()) return;
  impl_->stopping = true;
  net::post(impl_->ioc, [impl = impl_.get()] {
    beast::error_code ec;
    impl->acceptor.close(ec);
  });
  std::vector<std::shared_ptr<ClientConnection>> open_clients;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    for (const auto& [p, s] : impl_->open_clients) open_clients.push_back(s);
  }
  for (const auto& s : open_clients) s->close();
  open_clients.clear();
  // Give clients up to two seconds to answer the close, then stop regardless.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (std::chrono::steady_clock::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(impl_->mutex);
      if (impl_->open_clients.empty()) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  impl_->ioc.stop();
  impl_->thread.join();
  std::lock_guard<std::mutex> lock(impl_->mutex);
  impl_->open_clients.clear();
}

}  // namespace foxglove
}  // namespace ucon
