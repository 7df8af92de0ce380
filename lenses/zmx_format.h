// A subset of Zemax OpticStudio's sequential lens file (.zmx), read into a
// Prescription and written from one. The subset is what a stock lens or a
// simple eyepiece needs; everything that would change the geometry and is not
// in it is refused with the line, never skipped.
//
// The file is a list of lines "KEYWORD values...": system lines, then one
// block per surface opened by "SURF k" (k = 0, 1, ...), indentation free.
// Read (lengths in the file's lens units, UNIT MM, CM, IN or METER, MM when no
// UNIT line is given as in Zemax; meters in the Prescription):
//   SURF k       surfaces numbered 0, 1, 2, ... in order
//   TYPE         STANDARD (the default) or EVENASPH
//   CURV c       the curvature 1/R (sign as ours: + when the centre lies after the vertex)
//   CONI k       the conic constant (on a plane, CURV 0, it has no effect, as in Zemax)
//   PARM n a     EVENASPH only: the coefficient of r^(2n), n = 1..8. Ours starts
//                at r^4, so PARM n >= 2 is even_asphere[n - 2]; a nonzero PARM 1
//                (r^2) is refused: with CURV != 0 it is no conic. PARM on a
//                STANDARD surface is refused unless 0.
//   DISZ t       the axial gap to the next surface (INFINITY on the object only)
//   GLAS name    the medium after the surface, looked up in glass_catalog.h
//                (case-insensitive); the numbers after the name (solve type,
//                nd, vd, ...) are not read: the catalogue's formula is used.
//                Model glasses (___BLANK, MODEL), MIRROR and unknown names are refused.
//   DIAM s       the semi-diameter (clear aperture radius); 0: no aperture
//   CLAP 0 s     a circular aperture of radius s, overriding DIAM (an annular one is refused)
//   STOP         the aperture stop
//   MODE SEQ, MNUM 1   other modes and multi-configuration files are refused
// Ignored (they do not change the surfaces; solves and pickups store their
// results in CURV/DISZ): VERS NAME NOTE COMM PFIL LANG ENPD ENVD FNUM OBNA FLOA
// GFAC GCAT RAIM PUSH SDMA FTYP ROPD PICB XFLN YFLN FWGN VDXN VDYN VCXN VCYN
// VANN ZVDX ZVDY ZVCX ZVCY ZVAN WAVM WAVN WWGN WAVL WWGT PWAV POLS GLRS GSTD
// NSCD COFN BLNK TOL MOFF, and on surfaces HIDE MIRR SLAB POPS COAT (coatings:
// the prescription carries no transmission), MEMA (the mechanical edge), FLAP
// (the floating aperture, DIAM's copy), OBDC 0 0. Any other keyword, any other
// TYPE (COORDBRK, TOROIDAL, ...), surface tilts and decentres are refused.
//
// Object, image and gaps: surface 0 is the object, the last SURF the image.
// The Prescription holds surfaces 1 .. N-2 of the file in order, all of them
// (a dummy plane in air, a stop surface, stays, as a plane between two equal
// media); its material_before is the object surface's GLAS; each surface's
// thickness is its DISZ, so the last one's is the distance to the image
// surface (kept, unused by the trace). The object distance (DISZ of surface 0,
// INFINITY for a collimated object) is the conjugate, not the lens: it is not
// read, and the writer writes INFINITY. The object and image surfaces must be
// planes (CURV 0); their aperture, and the image's DISZ and GLAS, are not read.
//
// Encoding: UTF-8 (an optional BOM) or UTF-16LE with its BOM (as OpticStudio
// saves). UTF-16BE, UTF-32 and text with NUL bytes are refused. The keywords
// and numbers are ASCII; other bytes may appear only in ignored text lines, so
// Thorlabs' Latin-1 files ("Ø" in NAME) read as well.
//
// Every error is "<source>:<line>: <what>"; the reader never crashes on any
// input (fuzz/zmx_fuzz.cpp).
//
// Sources for the format: the .zmx readers of optiland
// (optiland/fileio/zemax/reader/parser.py) and ray-optics
// (src/rayoptics/zemax/zmxread.py), and files written by OpticStudio and by
// Thorlabs (optiland's tests/zemax_files/, e.g. lens_thorlabs_iso_8859_1.zmx).
#pragma once

#include <string>

#include "layerlab/lenses/lens_system.h"

namespace layerlab::lenses {

// Reads `text` (the file's bytes); `source_name` names it in errors. The result
// is checked as LensSystem checks it (an error names the surface's SURF line).
// Throws layerlab::Error.
Prescription ReadZmx(const std::string& text, const std::string& source_name);

// A .zmx (UTF-8, CRLF line ends) holding `prescription`, the object at
// infinity, the image plane at the last surface's thickness; `title` is the
// NAME line. Each number is written with the fewest significant digits that
// ReadZmx reads back to the same double: in millimeters (UNIT MM) when every
// number has such digits there, else in meters (UNIT METER, where every double
// has them; a lens read from inches may need it). So ReadZmx(WriteZmx(p)) == p
// field by field for a prescription read from a file (its aspheric terms have
// no trailing zeros), and writing what was read gives the same text again.
// Throws layerlab::Error for what the subset cannot hold (placements, Fresnel
// surfaces, more than 7 aspheric terms) or what LensSystem refuses.
std::string WriteZmx(const Prescription& prescription, const std::string& title);

}  // namespace layerlab::lenses
