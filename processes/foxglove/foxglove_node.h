#pragma once
// The Foxglove bridge as a node: subscribes to every channel that feeds a
// Foxglove topic (FoxgloveTranslator), translates what a client listens to
// and hands it to the WebSocket server (FoxgloveServer). It publishes
// nothing but its STATUS, so running it changes nothing for the estimator.

#include <memory>
#include <string>

#include "common/node.h"
#include "processes/foxglove/foxglove_options.h"
#include "processes/foxglove/foxglove_server.h"
#include "processes/foxglove/foxglove_translator.h"

namespace nadir {

class FoxgloveNode : public Node {
 public:
  // Throws std::runtime_error when the server cannot listen.
  FoxgloveNode(const FoxgloveOptions& options, Bus& bus);

  std::string name() const override { return "foxglove"; }
  std::vector<std::string> output_channels() const override { return {}; }
  StatusReport status() const override;

  int port() const { return server_->port(); }

 private:
  void on_message(const std::string& channel, const uint8_t* data, size_t size);

  FoxgloveTranslator translator_;
  std::unique_ptr<FoxgloveServer> server_;
  int64_t received_ = 0;
  int64_t undecodable_ = 0;
  std::string last_decode_error_;
  std::string port_note_;  // set when the configured port was taken and another was used
  std::vector<FoxgloveMessage> scratch_;
  mutable FoxgloveServerCounts last_counts_;  // at the previous status(): what changed since
};

std::unique_ptr<Node> make_foxglove_node(const Config& root, Bus& bus);
// "foxglove" in nadir_replay's catalog.
void register_foxglove_node(NodeRegistry& registry);

}  // namespace nadir
