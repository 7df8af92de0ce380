// framework/progress.h: the time left, and what each verbosity lets through.
#include <gtest/gtest.h>

#include "layerlab/framework/progress.h"

namespace layerlab {
namespace {

TEST(Progress, EtaIsTheTimeSoFarScaledByTheWorkLeft) {
  EXPECT_EQ(Progress::Eta(0, 10, 5), "");           // nothing done: no estimate
  EXPECT_EQ(Progress::Eta(10, 10, 5), "");          // all done
  EXPECT_EQ(Progress::Eta(5, 10, 5), "5.0 s");      // 5 s for half: 5 s more
  EXPECT_EQ(Progress::Eta(1, 4, 10), "30 s");       // 10 s a unit, 3 units left
  EXPECT_EQ(Progress::Eta(1, 50, 60), "49.0 min");  // 60 s x 49 = 2940 s
  EXPECT_EQ(Progress::Eta(1, 1000, 10), "2.8 h");   // 9990 s
}

// A note, a detail and three units of work; what reached stderr.
std::string Exercise() {
  testing::internal::CaptureStderr();
  {
    Note("a note");
    Detail("a detail");
    Progress p("work", 3);
    for (size_t k = 1; k <= 3; ++k) p.Update(k, "units");
    p.Finish("summary");
  }
  return testing::internal::GetCapturedStderr();
}

TEST(Progress, QuietSilencesProgressAndNotesVerboseShowsEveryUpdate) {
  const Verbosity before = CurrentVerbosity();
  SetVerbosity(Verbosity::kQuiet);
  EXPECT_EQ(Exercise(), "");

  SetVerbosity(Verbosity::kVerbose);
  const std::string verbose = Exercise();
  EXPECT_NE(verbose.find("a note\na detail\nwork: 1/3  "), std::string::npos) << verbose;
  EXPECT_NE(verbose.find("work: 2/3  "), std::string::npos) << verbose;
  EXPECT_NE(verbose.find("work: 3/3  "), std::string::npos) << verbose;
  EXPECT_NE(verbose.find("work: done in "), std::string::npos) << verbose;

  // Normal, without a terminal (as under ctest): short work says only its summary; no detail lines.
  SetVerbosity(Verbosity::kNormal);
  const std::string normal = Exercise();
  if (!Progress::Terminal()) {
    EXPECT_EQ(normal.rfind("a note\nwork: done in ", 0), 0u) << normal;
    EXPECT_NE(normal.find(": summary\n"), std::string::npos) << normal;
    EXPECT_EQ(normal.find("a detail"), std::string::npos) << normal;
  }
  SetVerbosity(before);
}

}  // namespace
}  // namespace layerlab
