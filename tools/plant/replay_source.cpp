#include "replay_source.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "dynweigh/hal/host/inputs_recording.hpp"

namespace dynweigh::tools {
namespace {

constexpr std::size_t kMaxLineLength = 4096;
constexpr std::size_t kMaxSamples = 10'000'000;  // 27 hours of jiffies

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, separator)) fields.push_back(field);
  return fields;
}

bool parse_long(const std::string& text, long& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtol(text.c_str(), &end, 10);
  return end && *end == '\0';
}

bool parse_raw(const std::string& text, std::int32_t& value) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || !end || *end != '\0') return false;
  value = std::int32_t(v < 0 ? v - 0.5 : v + 0.5);
  return true;
}

// std::getline that stops past kMaxLineLength and refuses bytes no text holds, so a binary or
// endless file is refused at once instead of parsed into a sample or read into memory whole.
bool read_text_line(std::istream& in, std::string& line, std::size_t number, const std::string& path) {
  line.clear();
  int c = 0;
  while ((c = in.get()) != std::char_traits<char>::eof() && c != '\n') {
    if (c == '\0' || (c < 0x20 && c != '\t' && c != '\r') || c == 0x7f) {
      throw std::runtime_error("replay file " + path + ": line " + std::to_string(number) +
                               " holds binary data (not a capture, a CSV or an inputs recording)");
    }
    if (line.size() == kMaxLineLength) {
      throw std::runtime_error("replay file " + path + ": line " + std::to_string(number) + " is too long");
    }
    line.push_back(char(c));
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return c != std::char_traits<char>::eof() || !line.empty();
}

// Each jiffy's raw sample as the indicator received it in a `dynweigh-fw --record` run.
std::vector<std::int32_t> recorded_inputs_samples(const std::string& path) {
  hal::host::InputsRecordingReader reader(path);
  std::vector<std::int32_t> samples;
  for (hal::host::RecordedJiffy jiffy; reader.next(jiffy);) {
    if (samples.size() == kMaxSamples) throw std::runtime_error("replay file " + path + " holds too many samples");
    samples.push_back(jiffy.load_cell.raw_counts);
  }
  if (samples.empty()) throw std::runtime_error("replay file " + path + " holds no samples");
  return samples;
}

}  // namespace

std::vector<std::int32_t> load_replay_samples(const std::string& path) {
  if (hal::host::InputsRecordingReader::is_recording(path)) return recorded_inputs_samples(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read replay file " + path);
  std::vector<std::int32_t> samples;
  std::string line;
  int raw_column = -1;
  bool first = true;
  for (std::size_t number = 1; read_text_line(in, line, number, path); ++number) {
    if (samples.size() == kMaxSamples) throw std::runtime_error("replay file " + path + " holds too many samples");
    if (first && line.find(',') != std::string::npos) {  // a CSV: find the raw column
      const auto header = split(line, ',');
      for (std::size_t i = 0; i < header.size(); ++i) {
        if (header[i] == "raw") raw_column = int(i);
      }
      if (raw_column < 0) throw std::runtime_error("replay CSV " + path + " has no 'raw' column");
      first = false;
      continue;
    }
    first = false;
    if (raw_column >= 0) {
      const auto fields = split(line, ',');
      std::int32_t raw = 0;
      if (std::size_t(raw_column) < fields.size() && parse_raw(fields[std::size_t(raw_column)], raw)) {
        samples.push_back(raw);
      }
      continue;
    }
    // readtestdata: exactly four integers; anything else (OK, prompts, RESULT lines) is skipped.
    std::istringstream words(line);
    std::string word[5];
    int count = 0;
    while (count < 5 && words >> word[count]) ++count;
    long values[4];
    if (count != 4) continue;
    bool ok = true;
    for (int i = 0; i < 4; ++i) ok = ok && parse_long(word[i], values[i]);
    if (ok) samples.push_back(std::int32_t(values[1]));
  }
  if (samples.empty()) throw std::runtime_error("replay file " + path + " holds no samples");
  return samples;
}

}  // namespace dynweigh::tools
