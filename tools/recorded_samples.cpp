#include "recorded_samples.hpp"

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "dynweigh/hal/host/inputs_recording.hpp"

namespace dynweigh::tools {
namespace {

// Reads lines of bounded length; refuses binary data instead of guessing at it.
class LineReader {
 public:
  explicit LineReader(const std::string& path) : file_(std::fopen(path.c_str(), "rb"), &std::fclose), path_(path) {
    if (!file_) throw std::runtime_error("cannot read " + path + ": " + std::strerror(errno));
  }

  bool next(std::string& line) {
    line.clear();
    ++number_;  // the line being read is the one an error names
    int c;
    while ((c = getc_unlocked(file_.get())) != EOF) {  // one reader thread: no per-character lock
      if (c == '\n') break;
      if (c == '\0' || (c < 0x20 && c != '\t' && c != '\r') || c == 0x7f) {
        fail("holds binary data, not text");
      }
      if (line.size() == kMaxSampleLineLength) fail("is longer than " + std::to_string(kMaxSampleLineLength) + " characters");
      line.push_back(char(c));
    }
    if (c == EOF && line.empty()) {
      --number_;
      return false;
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(path_ + ": line " + std::to_string(number_) + " " + what);
  }
  std::size_t number() const { return number_; }

 private:
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::string path_;
  std::size_t number_ = 0;
};

bool blank(const std::string& line) { return line.find_first_not_of(" \t") == std::string::npos; }

std::string trimmed(const std::string& text) {
  const auto b = text.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return text.substr(b, text.find_last_not_of(" \t") - b + 1);
}

// A whole-cell integer, or false.
bool parse_integer(const std::string& text, long long& value) {
  const std::string t = trimmed(text);
  if (t.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtoll(t.c_str(), &end, 10);
  return errno == 0 && *end == '\0';
}

// Splits into `cells`, reusing its strings: a replay reads millions of lines.
void split(const std::string& line, char separator, std::vector<std::string>& cells) {
  std::size_t count = 0, begin = 0;
  for (;;) {
    const std::size_t end = line.find(separator, begin);
    if (count == cells.size()) cells.emplace_back();
    cells[count++].assign(line, begin, end == std::string::npos ? std::string::npos : end - begin);
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  cells.resize(count);
}

std::int32_t as_raw(long long value, const LineReader& in) {
  if (value < INT32_MIN || value > INT32_MAX) in.fail("has a raw value outside 32 bits");
  return std::int32_t(value);
}

void check_room(const RecordedSamples& s, const LineReader& in) {
  if (s.samples.size() >= kMaxSamples) in.fail("exceeds " + std::to_string(kMaxSamples) + " samples, the most a replay takes");
}

void read_testdata(LineReader& in, std::string line, RecordedSamples& out) {
  out.format = "readtestdata";
  long long previous_jiffy = -1;
  do {
    const std::string t = trimmed(line);
    if (t.rfind("ERR", 0) == 0) in.fail("is the indicator's error '" + t + "', not test data");
    // The console's other lines around the data: OK, an echoed command, a prompt's text.
    if (t.empty() || std::isalpha(static_cast<unsigned char>(t[0]))) continue;
    std::istringstream fields(t);
    std::string word[5];
    int n = 0;
    while (n < 5 && fields >> word[n]) ++n;
    long long jiffy = 0, raw = 0, filtered = 0, marker = 0;
    if (n != 4 || !parse_integer(word[0], jiffy) || !parse_integer(word[1], raw) ||
        !parse_integer(word[2], filtered) || !parse_integer(word[3], marker)) {
      in.fail("is not '<jiffy> <raw> <filtered> <marker>'");
    }
    if (marker < 0 || marker > 2) in.fail("has marker " + std::to_string(marker) + " (0, 1 or 2)");
    // Jiffy 0 again: another printout follows the first (a capture of several test cycles).
    if (previous_jiffy >= 0 && jiffy != previous_jiffy + 1 && jiffy != 0) {
      in.fail("has jiffy " + std::to_string(jiffy) + " after " + std::to_string(previous_jiffy) + " (records must be consecutive)");
    }
    previous_jiffy = jiffy;
    check_room(out, in);
    out.samples.push_back({as_raw(raw, in), int(marker)});
  } while (in.next(line));
}

void read_csv(LineReader& in, const std::string& header, RecordedSamples& out) {
  out.format = "csv";
  std::vector<std::string> names, cells;
  split(header, ',', names);
  long raw_column = -1, valve_column = -1;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string name = trimmed(names[i]);
    if (name == "raw") raw_column = long(i);
    if (name == "valve" || name == "marker") valve_column = long(i);
  }
  if (raw_column < 0) in.fail("(the CSV header) has no 'raw' column");
  for (std::string line; in.next(line);) {
    if (blank(line)) continue;
    split(line, ',', cells);
    if (cells.size() != names.size()) {
      in.fail("has " + std::to_string(cells.size()) + " fields, the header " + std::to_string(names.size()));
    }
    long long raw = 0, valve = -1;
    if (!parse_integer(cells[std::size_t(raw_column)], raw)) in.fail("has a raw value that is not an integer");
    if (valve_column >= 0) {
      if (!parse_integer(cells[std::size_t(valve_column)], valve) || valve < 0 || valve > 2) {
        in.fail("has a valve value that is not 0, 1 or 2");
      }
    }
    check_room(out, in);
    out.samples.push_back({as_raw(raw, in), int(valve)});
  }
}

// Each jiffy's raw sample as the indicator received it, and the valve it commanded.
void read_inputs_recording(const std::string& path, RecordedSamples& out) {
  out.format = "inputs";
  hal::host::InputsRecordingReader reader(path);
  for (hal::host::RecordedJiffy jiffy; reader.next(jiffy);) {
    if (out.samples.size() >= kMaxSamples) {
      throw std::runtime_error(path + ": exceeds " + std::to_string(kMaxSamples) + " samples, the most a replay takes");
    }
    out.samples.push_back({jiffy.load_cell.raw_counts, jiffy.has_outputs ? int(jiffy.outputs.valve) : -1});
  }
}

}  // namespace

long RecordedSamples::first_open_jiffy() const {
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (samples[i].valve > 0) return long(i);
  }
  return -1;
}

RecordedSamples load_recorded_samples(const std::string& path) {
  RecordedSamples out;
  if (hal::host::InputsRecordingReader::is_recording(path)) {
    read_inputs_recording(path, out);
    if (out.samples.empty()) throw std::runtime_error(path + ": no samples");
    return out;
  }
  LineReader in(path);
  std::string first;
  while (in.next(first) && blank(first)) {
  }
  if (blank(first)) throw std::runtime_error(path + ": empty, no samples");
  if (first.find(',') != std::string::npos) {
    read_csv(in, first, out);
  } else {
    read_testdata(in, first, out);
  }
  if (out.samples.empty()) throw std::runtime_error(path + ": no samples");
  return out;
}

}  // namespace dynweigh::tools
