// Warnings: what a command finds that does not stop it but changes what its
// results mean (a frequency beyond what the display can show, a layer the eye
// cannot focus on, a target of another geometry than the display's, a solve
// that ends far below what the display reaches). Each is found where the
// knowledge is and kept as text with the result (DisplaySystem::warnings,
// SolverReport::warnings, ContrastWarnings); the command says it on stderr
// with SayWarnings and writes the same text into its report (report.json
// "warnings", and WarningLines in the text reports).
#pragma once

#include <string>
#include <vector>

namespace layerlab {

// "warning: <prefix><text>" on stderr, one line each.
void SayWarnings(const std::vector<std::string>& texts, const std::string& prefix = "");
// The same lines, for a text report.
std::string WarningLines(const std::vector<std::string>& texts);

}  // namespace layerlab
