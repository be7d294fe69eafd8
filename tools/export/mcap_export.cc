#include "tools/export/mcap_export.h"

#include <algorithm>
#include <vector>

#include "common/log_file.h"
#include "processes/foxglove/foxglove_schemas.h"
#include "processes/foxglove/foxglove_translator.h"
#include "tools/export/mcap_writer.h"

namespace nadir {

McapExportStats export_mcap(const std::string& log_path, const std::string& mcap_path,
                            const McapExportOptions& options) {
  LogReader reader(log_path);
  FoxgloveTranslatorOptions translator_options;
  translator_options.origin_from_ins = options.origin_from_ins;
  translator_options.origin = options.origin;
  translator_options.image_rate_hz = options.image_rate_hz;
  FoxgloveTranslator translator(translator_options);

  McapWriterOptions writer_options;
  writer_options.chunk_size = options.chunk_size;
  McapWriter writer(mcap_path, writer_options);
  std::map<std::string, uint16_t> schema_ids;
  std::vector<uint16_t> channel_ids;
  for (const FoxgloveTopic& t : translator.topics()) {
    auto it = schema_ids.find(t.schema_name);
    if (it == schema_ids.end())
      it = schema_ids.emplace(t.schema_name, writer.add_schema(t.schema_name, "jsonschema",
                                                               foxglove_schemas::schema_text(t.schema_name)))
               .first;
    channel_ids.push_back(writer.add_channel(it->second, t.name, "json", {{"lcm_channel", t.lcm_channel}}));
  }
  std::vector<uint32_t> sequences(channel_ids.size(), 0);

  McapExportStats stats;
  const std::vector<std::string> exported = translator.lcm_channels();
  LogEvent event;
  std::vector<FoxgloveMessage> messages;
  while (reader.next(&event)) {
    ++stats.log_events;
    if (std::find(exported.begin(), exported.end(), event.channel) == exported.end()) {
      ++stats.skipped[event.channel];
      continue;
    }
    messages.clear();
    std::string reason;
    if (!translator.translate(event.channel, event.data, event.size, {}, &messages, &reason)) {
      ++stats.undecodable;
      continue;
    }
    ++stats.lcm_messages[event.channel];
    const uint64_t log_time = static_cast<uint64_t>(std::max<int64_t>(event.timestamp, 0)) * 1000;
    for (const FoxgloveMessage& m : messages) {
      writer.write_message(channel_ids[m.topic], sequences[m.topic]++, log_time,
                           static_cast<uint64_t>(std::max<int64_t>(m.time_ns, 0)),
                           reinterpret_cast<const uint8_t*>(m.json.data()), m.json.size());
      ++stats.messages;
    }
  }
  stats.images_decimated = translator.images_decimated();
  stats.corrupt_records = reader.corrupt_records();
  writer.close();
  stats.chunks = writer.chunk_count();
  return stats;
}

}  // namespace nadir
