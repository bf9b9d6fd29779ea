#pragma once
// A furniture maker's cut list: for each visible body of the part, the
// stock it is cut from (length x width x thickness, mm) and how many.
//
// What a body is: the document's solid read as an assembly.
// - A union is a set of bodies: those of each visible child.
// - A difference is the bodies of its first visible child, each with the
//   other children cut away; an intersection likewise, each clipped by the
//   others (a floor plane, say).
// - Blends are left out of the measurement: a smooth union still joins
//   separate pieces of stock (the fillet is shaping and glue), and a blended
//   cut changes an edge, not the stock's size.
// - An array or mirror (of a body set) repeats its child's bodies: the
//   quantity multiplies (count product; 2 for a mirror), measured on the
//   first copy.
// - Anything else (a primitive, a smooth boolean, an offset, a shell) is one
//   body.
// - A tenon is part of its board's stock: a body of a union that touches a
//   larger body of the same union, lies within that body's cross-section
//   (filling at least a quarter of its thickness and half of its width) and
//   reaches beyond its end is joined to it; the board's row measures both
//   and names the tenons (CutListRow::joined). A dowel, a leg against an
//   apron, a shelf in a housing stay bodies of their own.
// Each body is measured in its own frame (its node's local axes, the
// transforms from the root down to it undone), so a splayed leg lists the
// stock it is cut from, not its footprint. The dimensions are the tight
// bounds of the body after its cuts (TightBounds.hpp), sorted: length >=
// width >= thickness.

#include "kerf/document/Document.hpp"
#include "kerf/document/LengthFormat.hpp"

#include <string>
#include <vector>

namespace kerf {

struct CutListRow {
    std::string nodeId;
    std::string name;     // the node's name, its difference's, the first below it (through first children), or its id
    long quantity = 1;
    double length = 0.0;  // mm, the largest local extent
    double width = 0.0;
    double thickness = 0.0;
    double uncertainty = 0.0; // mm: how far the dimensions may be off (the search's tolerance)
    bool unbounded = false;   // an unbounded body (a lone halfspace): no dimensions
    std::vector<std::string> joined; // names of the tenons measured with it (cut from its stock)
};

/// The cut list of `doc`'s part, bodies in tree order. Empty bodies are left
/// out. `tolerance` (mm) is the tight-bounds tolerance.
std::vector<CutListRow> cutList(const Document& doc, double tolerance = 1e-2);

/// A row's part as shown and written: its name, and the tenons joined to it
/// ("Rail (with its tenons: Tenon, Tenon)").
std::string cutListName(const CutListRow& row);

/// The rows as CSV (RFC 4180: quoted where needed, CRLF line ends), with a
/// header: Part,Id,Quantity,Length (mm),Width (mm),Thickness (mm); in
/// inches "Length (in)", ... with decimal inches to a ten-thousandth (what
/// a spreadsheet or a cutting optimizer reads).
std::string cutListCsv(const std::vector<CutListRow>& rows, LengthUnit unit = LengthUnit::Millimetres);

} // namespace kerf
