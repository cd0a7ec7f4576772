#include "eval/confidence_eval.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numeric>
#include <sstream>

#include "eval/score_json.h"

namespace semvox {

ConfidenceScores ScoreConfidence(const std::vector<float>& confidence, const std::vector<uint8_t>& right) {
  ConfidenceScores s;
  const size_t n = std::min(confidence.size(), right.size());
  std::vector<std::pair<float, uint8_t>> scored;
  scored.reserve(n);
  for (size_t i = 0; i < n; ++i)
    if (!std::isnan(confidence[i])) scored.emplace_back(std::clamp(confidence[i], 0.f, 1.f), right[i] ? 1 : 0);
  s.scored = scored.size();
  if (scored.empty()) {
    const Score none{false, 0.0, "no prediction with a confidence"};
    s.mean_confidence = s.accuracy = s.ece = s.auroc = none;
    s.share_above_05 = s.accuracy_above_05 = s.share_above_08 = s.accuracy_above_08 = none;
    return s;
  }
  const double total = double(scored.size());
  double conf_sum = 0, right_sum = 0;
  std::array<double, kReliabilityBins> bin_conf{}, bin_right{};
  size_t above[2] = {0, 0}, above_right[2] = {0, 0};
  for (const auto& [c, r] : scored) {
    conf_sum += c, right_sum += r;
    const int b = std::min(kReliabilityBins - 1, int(c * kReliabilityBins));
    ++s.bins[size_t(b)].count;
    bin_conf[size_t(b)] += c, bin_right[size_t(b)] += r;
    for (int k = 0; k < 2; ++k)
      if (c >= (k == 0 ? 0.5f : 0.8f)) ++above[k], above_right[k] += r;
  }
  double ece = 0;
  for (int b = 0; b < kReliabilityBins; ++b) {
    ReliabilityBin& bin = s.bins[size_t(b)];
    if (!bin.count) continue;
    bin.mean_confidence = bin_conf[size_t(b)] / double(bin.count);
    bin.accuracy = bin_right[size_t(b)] / double(bin.count);
    ece += double(bin.count) / total * std::abs(bin.accuracy - bin.mean_confidence);
  }
  const std::string of = std::to_string(scored.size()) + " predictions";
  s.mean_confidence = Score{true, conf_sum / total, of};
  s.accuracy = Score{true, right_sum / total, of};
  s.ece = Score{true, ece, std::to_string(kReliabilityBins) + " equal-width bins"};
  for (int k = 0; k < 2; ++k) {
    Score& share = k == 0 ? s.share_above_05 : s.share_above_08;
    Score& acc = k == 0 ? s.accuracy_above_05 : s.accuracy_above_08;
    share = Score{true, double(above[k]) / total, of};
    acc = above[k] ? Score{true, double(above_right[k]) / double(above[k]), std::to_string(above[k]) + " predictions"}
                   : Score{false, 0.0, "none that confident"};
  }
  // AUROC by ranks (Mann-Whitney U, ties sharing their mean rank).
  const size_t positives = size_t(right_sum), negatives = scored.size() - positives;
  if (positives == 0 || negatives == 0) {
    s.auroc = Score{false, 0.0, positives == 0 ? "every prediction wrong" : "every prediction right"};
    return s;
  }
  std::sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  double rank_sum = 0;
  for (size_t i = 0; i < scored.size();) {
    size_t j = i;
    while (j < scored.size() && scored[j].first == scored[i].first) ++j;
    const double mean_rank = 0.5 * double(i + 1 + j);  // Ranks i+1 .. j.
    for (size_t k = i; k < j; ++k)
      if (scored[k].second) rank_sum += mean_rank;
    i = j;
  }
  const double u = rank_sum - double(positives) * double(positives + 1) / 2.0;
  s.auroc = Score{true, u / (double(positives) * double(negatives)),
                  std::to_string(positives) + " right, " + std::to_string(negatives) + " wrong"};
  return s;
}

std::string ConfidenceTable(const ConfidenceScores& s) {
  std::ostringstream os;
  const auto row = [&](const char* name, const Score& v) { AppendScoreRow(os, name, v); };
  row("confidence: mean", s.mean_confidence);
  row("confidence: ECE", s.ece);
  os << "  " << std::left << std::setw(26) << "confidence: AUROC" << std::right << std::setw(10);
  if (s.auroc.present) os << std::fixed << std::setprecision(3) << s.auroc.value << "  ";
  else os << "absent";
  os << "   (" << s.auroc.note << ")\n";
  row("share >= 0.5", s.share_above_05);
  row("  right among them", s.accuracy_above_05);
  row("share >= 0.8", s.share_above_08);
  row("  right among them", s.accuracy_above_08);
  os << "  reliability (confidence bin: predictions, mean confidence, accuracy):\n";
  for (int b = 0; b < kReliabilityBins; ++b) {
    const ReliabilityBin& bin = s.bins[size_t(b)];
    os << "    [" << std::fixed << std::setprecision(1) << b / 10.0 << ", " << (b + 1) / 10.0 << (b + 1 == kReliabilityBins ? "]" : ")")
       << std::setw(10) << bin.count;
    if (bin.count) os << std::setw(8) << std::setprecision(3) << bin.mean_confidence << std::setw(8) << bin.accuracy;
    os << "\n";
  }
  return os.str();
}

}  // namespace semvox
