#pragma once
// A bench series as a job of the scenario grid: its key (what it runs) and its result as one row
// of text that reads back to the very same numbers (%.17g), so that a row computed by another
// rank, or read from a journal, prints the same bytes as one computed here.
#include <string>
#include <vector>

#include "fill_series.hpp"

namespace dynweigh::tools {

// "strategy=model knob=0 scene=default target_g=10000"
std::string series_key(const SeriesSpec& spec, const std::vector<Scenario>& scenarios);

std::string encode_series_row(const SeriesResult& result);
// Throws on a row that does not hold every field.
SeriesResult decode_series_row(const SeriesSpec& spec, const std::string& row);

}  // namespace dynweigh::tools
