#include "plant_console_command.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace dynweigh::tools {
namespace {

std::string plant_line(const sim::Plant& plant) {
  const sim::PlantTruth& t = plant.truth();
  char text[256];
  std::snprintf(text, sizeof text,
                "PLANT silo_kg=%.3f refilled_kg=%.3f refilling=%d in_flight_kg=%.3f container_kg=%.3f "
                "discharged_kg=%.3f gate=%d\n",
                t.silo_kg, t.refilled_kg, t.refilling ? 1 : 0, t.in_flight_kg, t.static_kg, t.discharged_kg,
                static_cast<int>(plant.gate_feedback()));
  return text;
}

}  // namespace

bool answer_plant_command(const std::string& line, sim::Plant& plant, std::string& answer) {
  std::istringstream words(line);
  std::string word;
  if (!(words >> word) || word != "plant") return false;
  std::string sub;
  if (!(words >> sub)) {
    answer = plant_line(plant) + "OK\n";
    return true;
  }
  std::string kg_text, extra;
  if (sub == "refill" && !(words >> kg_text)) {
    plant.start_refill();
    answer = "OK\n";
    return true;
  }
  if (sub == "refill" && !(words >> extra)) {
    char* end = nullptr;
    const double kg = std::strtod(kg_text.c_str(), &end);
    if (end && *end == '\0' && std::isfinite(kg) && kg > 0.0 && kg <= 1e6) {
      plant.add_to_silo(kg);
      answer = "OK\n";
      return true;
    }
  }
  answer = "ERR 2 usage: plant | plant refill [<kg>]\n";
  return true;
}

}  // namespace dynweigh::tools
