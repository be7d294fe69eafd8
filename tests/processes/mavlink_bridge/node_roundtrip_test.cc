// The codec against an independent MAVLink implementation, node-mavlink
// (npm), over real UDP loopback sockets, both ways, for every message nadir
// reads or writes: random field values (seeded) encoded by us are decoded by
// node-mavlink with identical values (v2, and v1 for ids below 256), and
// frames node-mavlink encodes from random values are decoded by us with
// identical values. Floats compare bit for bit (as float32), integers exactly.

#include <gtest/gtest.h>
#include <poll.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <sys/stat.h>

#include "processes/mavlink_bridge/mavlink_frame.h"
#include "processes/mavlink_bridge/udp_link.h"
#include "tests/common/test_support.h"

namespace nadir::mavlink {
namespace {

// --- a JSON reader just large enough for the peer's output ---------------
struct Json {
  enum Kind { kNull, kNumber, kString, kArray, kObject } kind = kNull;
  std::string text;  // number or string, as written
  std::vector<Json> items;
  std::map<std::string, Json> fields;
};

class JsonReader {
 public:
  explicit JsonReader(const std::string& s) : s_(s) {}
  Json value() {
    skip();
    Json v;
    if (s_[i_] == '{') {
      v.kind = Json::kObject;
      ++i_;
      for (skip(); s_[i_] != '}'; skip()) {
        const std::string key = string();
        skip();
        ++i_;  // ':'
        v.fields[key] = value();
        skip();
        if (s_[i_] == ',') ++i_;
      }
      ++i_;
    } else if (s_[i_] == '[') {
      v.kind = Json::kArray;
      ++i_;
      for (skip(); s_[i_] != ']'; skip()) {
        v.items.push_back(value());
        skip();
        if (s_[i_] == ',') ++i_;
      }
      ++i_;
    } else if (s_[i_] == '"') {
      v.kind = Json::kString;
      v.text = string();
    } else if (s_.compare(i_, 4, "null") == 0) {
      i_ += 4;
    } else {
      v.kind = Json::kNumber;
      const size_t start = i_;
      while (i_ < s_.size() && std::string("+-.eE0123456789").find(s_[i_]) != std::string::npos) ++i_;
      v.text = s_.substr(start, i_ - start);
    }
    return v;
  }

 private:
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  std::string string() {
    std::string out;
    for (++i_; s_[i_] != '"'; ++i_) out += s_[i_];
    ++i_;
    return out;
  }
  const std::string& s_;
  size_t i_ = 0;
};

// --- field visitors ------------------------------------------------------
struct Randomize {
  std::mt19937_64& rng;
  void extensions() {}
  template <class T>
  void operator()(const char*, T& v) {
    if constexpr (std::is_floating_point_v<T>) {
      v = static_cast<T>(std::uniform_real_distribution<double>(-1e4, 1e4)(rng));
    } else {
      v = static_cast<T>(rng());
    }
  }
  template <class T, size_t N>
  void operator()(const char* name, std::array<T, N>& a) {
    for (T& v : a) (*this)(name, v);
  }
};

template <class T>
std::string json_number(T v) {
  char text[64];
  if constexpr (std::is_floating_point_v<T>) {
    std::snprintf(text, sizeof text, "%.9g", static_cast<double>(v));
  } else if constexpr (std::is_signed_v<T>) {
    std::snprintf(text, sizeof text, "%lld", static_cast<long long>(v));
  } else {
    std::snprintf(text, sizeof text, "%llu", static_cast<unsigned long long>(v));
  }
  // 64-bit integers as strings: JSON numbers are doubles.
  return sizeof(T) == 8 && std::is_integral_v<T> ? "\"" + std::string(text) + "\"" : std::string(text);
}

struct WriteJson {
  std::string out;
  bool extension = false;
  void extensions() { extension = true; }
  void add(const char* name, const std::string& value) {
    out += (out.empty() ? "" : ", ") + std::string("\"") + name + "\": " + value;
  }
  template <class T>
  void operator()(const char* name, const T& v) { add(name, json_number(v)); }
  template <class T, size_t N>
  void operator()(const char* name, const std::array<T, N>& a) {
    std::string list;
    for (const T& v : a) list += (list.empty() ? "" : ", ") + json_number(v);
    add(name, "[" + list + "]");
  }
};

// Compares a decoded message with node-mavlink's JSON of it, field by field.
struct CompareJson {
  const Json& fields;
  std::string message;
  bool in_extensions = false;
  bool with_extensions = true;  // v1 frames carry none: node gives zeros
  int compared = 0;
  void extensions() { in_extensions = true; }
  template <class T>
  void check(const char* name, const T& expected, const Json& got) {
    const T want = in_extensions && !with_extensions ? T{} : expected;
    if constexpr (std::is_floating_point_v<T>) {
      const float value = static_cast<float>(std::strtod(got.text.c_str(), nullptr));
      EXPECT_EQ(value, static_cast<float>(want)) << message << "." << name << " = " << got.text;
    } else if constexpr (std::is_signed_v<T>) {
      EXPECT_EQ(std::strtoll(got.text.c_str(), nullptr, 10), static_cast<long long>(want)) << message << "." << name;
    } else {
      EXPECT_EQ(std::strtoull(got.text.c_str(), nullptr, 10), static_cast<unsigned long long>(want))
          << message << "." << name;
    }
    ++compared;
  }
  template <class T>
  void operator()(const char* name, const T& v) {
    const auto it = fields.fields.find(name);
    ASSERT_NE(it, fields.fields.end()) << message << " has no field " << name << " in node-mavlink's decode";
    check(name, v, it->second);
  }
  template <class T, size_t N>
  void operator()(const char* name, const std::array<T, N>& a) {
    const auto it = fields.fields.find(name);
    ASSERT_NE(it, fields.fields.end()) << message << " has no field " << name;
    ASSERT_EQ(it->second.items.size(), N) << message << "." << name;
    for (size_t i = 0; i < N; ++i) check(name, a[i], it->second.items[i]);
  }
};

// --- the node peer ------------------------------------------------------
std::string node_modules() {
  for (const std::string& dir : {std::string(NADIR_BINARY_DIR), std::string(NADIR_SOURCE_DIR) + "/build"}) {
    const std::string path = dir + "/node_mavlink/node_modules";
    struct stat st{};
    if (::stat((path + "/node-mavlink/package.json").c_str(), &st) == 0) return path;
  }
  return "";
}

std::string peer_command(const std::string& args) {
  return "NODE_PATH='" + node_modules() + "' node '" NADIR_SOURCE_DIR
         "/tests/processes/mavlink_bridge/mavlink_peer.js' " + args;
}

class NodeRoundTrip : public ::testing::Test {
 protected:
  void SetUp() override {
    if (node_modules().empty()) {
      FAIL() << "node-mavlink is not installed: run launch_scripts/setup.sh --tests, or "
                "tests/processes/mavlink_bridge/install_node_mavlink.sh " NADIR_BINARY_DIR " (outside the netns)";
    }
  }
};

template <class F>
void for_each_with_random_values(std::mt19937_64& rng, F&& f) {
  for_each_message_type([&](auto m) {
    Randomize r{rng};
    decltype(m)::visit(m, r);
    f(m);
  });
}

TEST_F(NodeRoundTrip, NodeMavlinkDecodesWhatWeEncode) {
  std::mt19937_64 rng(2019);
  FrameEncoder encoder(11, 197);
  struct Sent {
    std::function<void(const Json&, bool)> compare;
    uint32_t id;
    int version;
    uint8_t seq;
  };
  std::vector<Sent> sent;
  std::vector<std::vector<uint8_t>> frames;
  for (int version : {2, 1}) {
    for_each_with_random_values(rng, [&](auto m) {
      using M = decltype(m);
      if (version == 1 && M::kId > 255) return;
      sent.push_back({[m](const Json& fields, bool v1) {
                        CompareJson c{fields, M::kName};
                        c.with_extensions = !v1;
                        M::visit(m, c);
                        EXPECT_GT(c.compared, 0);
                      },
                      M::kId, version, encoder.next_seq()});
      frames.push_back(encoder.encode(m, version));
    });
  }
  FILE* peer = ::popen(peer_command("listen " + std::to_string(sent.size()) + " 20000").c_str(), "r");
  ASSERT_NE(peer, nullptr);
  char line[65536];
  ASSERT_NE(std::fgets(line, sizeof line, peer), nullptr);
  const int port = std::atoi(line + 5);  // "PORT n"
  ASSERT_GT(port, 0) << line;
  mavlink_bridge::UdpLink link(false, "127.0.0.1:0", "127.0.0.1:" + std::to_string(port));
  link.open();
  for (const auto& f : frames) ASSERT_TRUE(link.send(f.data(), f.size()));
  size_t got = 0;
  while (std::fgets(line, sizeof line, peer)) {
    const std::string text(line);
    const Json packet = JsonReader(text).value();
    ASSERT_LT(got, sent.size());
    const Sent& s = sent[got];
    EXPECT_EQ(std::stoul(packet.fields.at("msgid").text), s.id);
    EXPECT_EQ(std::stoi(packet.fields.at("version").text), s.version);
    EXPECT_EQ(std::stoi(packet.fields.at("seq").text), s.seq);
    EXPECT_EQ(std::stoi(packet.fields.at("sysid").text), 11);
    EXPECT_EQ(std::stoi(packet.fields.at("compid").text), 197);
    s.compare(packet.fields.at("fields"), s.version == 1);
    ++got;
  }
  ::pclose(peer);
  EXPECT_EQ(got, sent.size()) << "node-mavlink decoded only " << got << " of " << sent.size() << " frames";
  std::printf("node-mavlink decoded %zu frames we encoded (11 messages v2, 9 v1)\n", got);
}

TEST_F(NodeRoundTrip, WeDecodeWhatNodeMavlinkEncodes) {
  std::mt19937_64 rng(2020);
  nadir::testing::TempDir tmp("mavlink_node");
  const std::string file = tmp.file("messages.jsonl");
  std::ofstream out(file);
  std::vector<std::function<void(const Frame&)>> checks;
  uint8_t seq = 0;
  for (int version : {2, 1}) {
    for_each_with_random_values(rng, [&](auto m) {
      using M = decltype(m);
      if (version == 1 && M::kId > 255) return;
      WriteJson w;
      M::visit(m, w);
      out << "{\"name\": \"" << M::kName << "\", \"version\": " << version << ", \"sysid\": 9, \"compid\": 8, "
          << "\"seq\": " << int{seq} << ", \"fields\": {" << w.out << "}}\n";
      checks.push_back([m, version, seq](const Frame& f) {
        EXPECT_EQ(f.msgid, M::kId);
        EXPECT_EQ(f.version, version);
        EXPECT_EQ(f.seq, seq);
        EXPECT_EQ(f.sysid, 9);
        EXPECT_EQ(f.compid, 8);
        const M got = f.decode<M>();
        // node-mavlink 2.3.0 writes the extension fields into MAVLink 1
        // frames too (the reference C library leaves them out); both are
        // accepted, and what the frame holds must be what node was given.
        EXPECT_GE(f.payload_length, version == 1 ? message_info<M>().base_length : 1);
        const std::vector<uint8_t> full = encode_payload(m);
        const M want = decode_payload<M>(full.data(), version == 1 ? f.payload_length : full.size());
        EXPECT_EQ(encode_payload(got), encode_payload(want)) << M::kName << " v" << version;
      });
      ++seq;
    });
  }
  out.close();
  mavlink_bridge::UdpLink link(true, "127.0.0.1:0", "");
  link.open();
  const std::string target = "127.0.0.1:" + std::to_string(link.local_port());
  const int status = std::system(peer_command("send " + target + " " + file).c_str());
  ASSERT_EQ(status, 0);
  FrameParser parser;
  std::vector<Frame> frames;
  std::vector<uint8_t> datagram;
  while (frames.size() < checks.size()) {
    pollfd pfd{link.fd(), POLLIN, 0};
    if (::poll(&pfd, 1, 5000) <= 0) break;
    while (link.receive(&datagram)) {
      parser.feed(datagram.data(), datagram.size(), 0, 0.0, &frames);
      parser.end_of_datagram(&frames);
    }
  }
  ASSERT_EQ(frames.size(), checks.size());
  EXPECT_EQ(parser.counts().rejected_spans, 0);
  // Datagrams on loopback keep their order.
  for (size_t i = 0; i < frames.size(); ++i) checks[i](frames[i]);
  std::printf("decoded %zu frames node-mavlink encoded (%lld v1)\n", frames.size(),
              static_cast<long long>(parser.counts().frames_v1));
}

}  // namespace
}  // namespace nadir::mavlink
