// The glass catalogue against the manufacturers' published values: nd and vd
// of each Schott glass to the catalogue's rounding, N-BK7's nF, nC and ne from
// its data sheet, the plastics' nd from their makers' data sheets.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "layerlab/lenses/glass_catalog.h"
#include "layerlab/tests/test_util.h"

namespace layerlab::lenses {
namespace {

using layerlab::testing::ErrorOf;

struct Published {
  const char* name;
  double nd;  // SCHOTT optical glass data sheets (2017), 5 decimals
  double vd;  // 2 decimals
};

// Written here from the data sheets, not read from the catalogue entries.
constexpr Published kSchott[] = {
    {"N-BK7", 1.51680, 64.17}, {"N-SF11", 1.78472, 25.68},  {"N-F2", 1.62005, 36.43}, {"N-LAK22", 1.65113, 55.89},
    {"N-SF5", 1.67271, 32.25}, {"N-BAF10", 1.67003, 47.11}, {"SF5", 1.67270, 32.21},
};

TEST(LensGlassCatalog, SchottGlassesMatchTheirPublishedNdAndVd) {
  for (const Published& p : kSchott) {
    const Material& m = FindMaterial(p.name);
    // nd is published to 5 decimals (rounding 5e-6), the Sellmeier fit is
    // within a few 1e-6 of the melt's nominal values.
    EXPECT_NEAR(m.Index(587.5618e-9), p.nd, 1e-5) << p.name;
    // vd to 2 decimals; (nd - 1) / (nF - nC) amplifies the fit's 1e-6 to ~0.01.
    EXPECT_NEAR(AbbeNumber(m), p.vd, 0.02) << p.name;
  }
}

TEST(LensGlassCatalog, NBk7MatchesItsDataSheetAtTheOtherLines) {
  const Material& bk7 = FindMaterial("N-BK7");
  // SCHOTT N-BK7 data sheet: nF 1.52238, nC 1.51432, ne 1.51872, n(632.8 nm) 1.51509.
  EXPECT_NEAR(bk7.Index(486.1327e-9), 1.52238, 1e-5);
  EXPECT_NEAR(bk7.Index(656.2725e-9), 1.51432, 1e-5);
  EXPECT_NEAR(bk7.Index(546.0740e-9), 1.51872, 1e-5);
  EXPECT_NEAR(bk7.Index(632.8e-9), 1.51509, 1e-5);
}

TEST(LensGlassCatalog, PlasticsMatchTheirMakersPublishedNd) {
  // Sultanova et al.'s fits against the makers' data sheets, published to 3
  // decimals (and measured on other samples: molding grade, thermal history):
  // PLEXIGLAS (Evonik) PMMA 1.491; Makrolon (Covestro) PC 1.586; ZEONEX E48R (Zeon) 1.531.
  EXPECT_NEAR(FindMaterial("PMMA").Index(587.56e-9), 1.491, 1e-3);
  EXPECT_NEAR(FindMaterial("PC").Index(587.56e-9), 1.586, 2e-3);
  EXPECT_NEAR(FindMaterial("E48R").Index(587.56e-9), 1.531, 1e-3);
}

TEST(LensGlassCatalog, AirIsOne) { EXPECT_EQ(FindMaterial("air").Index(550e-9), 1.0); }

TEST(LensGlassCatalog, WavelengthOutsideTheFormulasRangeIsRefused) {
  EXPECT_EQ(ErrorOf([] { FindMaterial("N-BK7").Index(250e-9); }),
            "N-BK7: 250 nm lies outside the range of its dispersion formula, 300 nm to 2500 nm (SCHOTT optical "
            "glass catalogue, Zemax edition 2017-01-20b)");
  EXPECT_EQ(ErrorOf([] { FindMaterial("PMMA").Index(1.1e-6); }),
            "PMMA: 1100 nm lies outside the range of its dispersion formula, 436.8 nm to 1052 nm (Sultanova, "
            "Kasarova, Nikolov, Acta Phys. Pol. A 116, 585 (2009))");
  EXPECT_NE(ErrorOf([] { FindMaterial("PMMA").Index(436.8e-9); }).find("no error"), std::string::npos);
  EXPECT_NE(ErrorOf([] { FindMaterial("N-BK7").Index(NAN); }), "no error");
}

TEST(LensGlassCatalog, UnknownNameListsTheKnownOnes) {
  EXPECT_EQ(ErrorOf([] { FindMaterial("n-bk7"); }),
            "unknown material \"n-bk7\" (the catalogue knows air, N-BK7, N-SF11, N-F2, N-LAK22, N-SF5, N-BAF10, SF5, "
            "PMMA, PC, E48R)");
}

}  // namespace
}  // namespace layerlab::lenses
