// A geosynthetic-lined landfill side slope, 3H:1V, 10 m high (31.6 m along the slope), in plane
// strain per metre width.
//
// - Subgrade: the natural ground, from x = -10 (the cell floor) to x = 42 (behind the crest), down
//   to y = -6.
// - Clay liner: 0.6 m (vertically) of compacted clay on the floor, the slope and the crest up to the
//   anchor trench.
// - Liner line "liner": the top of the clay, from the left end of the floor (x = -10) over the toe
//   (0, 0) and up the slope to the crest (30, 10), 1.5 m along the crest, then down the wall of a
//   1 m x 1 m anchor trench and along its bottom to (32.5, 9). The geomembrane, the geotextile and
//   the geogrid all lie along it (a stack) and end in the trench.
// - Trench: the anchor trench's backfill (x = 31.5 to 32.5, y = 9 to 10).
// - Cover: 0.6 m of cover soil (normal to the slope) over the liner, from x = -10 to x = 36 on the
//   crest, placed in six parts from the toe up: "lift-1" (the floor and the slope up to x = 6),
//   "lift-2" to "lift-5" (x = 6-12, 12-18, 18-24, 24-30) and "lift-6" (the crest, over the trench).
//
// First-order triangles (a reinforcement runs along linear element sides). The .msh is shipped:
// a different Gmsh version may number the nodes differently. Regenerate with:
//   gmsh landfill-slope.geo -2 -format msh41 -o landfill-slope.msh
// Units: metres.

fine = 0.3;    // cover, clay, trench
coarse = 2.5;  // the depth of the subgrade

t = 0.6;                   // clay thickness, vertical
c = 0.6 * Sqrt(10) / 3;    // cover thickness 0.6 normal to a 3H:1V slope, vertical: 0.632

// the liner line
Point(1) = {-10, 0, 0, fine};      // A: left end of the floor (the head)
Point(2) = {0, 0, 0, fine};        // B: toe
Point(3) = {30, 10, 0, fine};      // C: crest
Point(4) = {31.5, 10, 0, fine};    // D: trench, near edge
Point(5) = {31.5, 9, 0, fine};     // E: trench bottom, near
Point(6) = {32.5, 9, 0, fine};     // F: trench bottom, far (the tail)
// clay bottom
Point(7) = {-10, -t, 0, fine};
Point(8) = {0, -t, 0, fine};
Point(9) = {30, 10 - t, 0, fine};
Point(10) = {31.5, 10 - t, 0, fine};
// subgrade
Point(11) = {-10, -6, 0, coarse};
Point(12) = {42, -6, 0, coarse};
Point(13) = {42, 10, 0, 1.0};
Point(14) = {32.5, 10, 0, fine};   // trench top, far edge
Point(15) = {36, 10, 0, fine};     // end of the cover on the crest
// cover top
Point(16) = {-10, 0.6, 0, fine};
Point(17) = {-c * 3 + 1.8, 0.6, 0, fine};      // slope offset line meets y = 0.6
Point(18) = {3 * (10.6 - c), 10.6, 0, fine};  // ... meets y = 10.6
Point(19) = {36, 10.6, 0, fine};
// lift boundaries on the slope: x = 6, 12, 18, 24 from the liner up to the cover's top
For k In {1:4}
  Point(20 + k) = {6 * k, 2 * k, 0, fine};
  Point(30 + k) = {6 * k, 2 * k + c, 0, fine};
EndFor
Point(35) = {30, 10.6, 0, fine};   // above the crest

// liner: A-B, B-21, 21-22, 22-23, 23-24, 24-C, C-D, D-10-E (the trench wall, split where the
// clay meets the subgrade), E-F
Line(1) = {1, 2};
Line(2) = {2, 21};
Line(3) = {21, 22};
Line(4) = {22, 23};
Line(5) = {23, 24};
Line(6) = {24, 3};
Line(7) = {3, 4};
Line(8) = {4, 10};
Line(33) = {10, 5};
Line(9) = {5, 6};
// clay
Line(10) = {7, 8};
Line(11) = {8, 9};
Line(12) = {9, 10};
Line(14) = {1, 7};
// subgrade
Line(15) = {7, 11};
Line(16) = {11, 12};
Line(17) = {12, 13};
Line(18) = {13, 15};
Line(19) = {15, 14};
Line(20) = {14, 6};
// trench top
Line(22) = {4, 14};
// cover
Line(23) = {1, 16};
Line(24) = {16, 17};
Line(25) = {17, 31};
Line(26) = {31, 32};
Line(27) = {32, 33};
Line(28) = {33, 34};
Line(29) = {34, 18};
Line(30) = {18, 35};
Line(31) = {35, 19};
Line(32) = {19, 15};
For k In {1:4}
  Line(40 + k) = {20 + k, 30 + k};
EndFor
Line(45) = {3, 35};

// surfaces
Curve Loop(1) = {10, 11, 12, -8, -7, -6, -5, -4, -3, -2, -1, 14};   // clay
Plane Surface(1) = {1};
Curve Loop(2) = {15, 16, 17, 18, 19, 20, -9, -33, -12, -11, -10};   // subgrade
Plane Surface(2) = {2};
Curve Loop(3) = {8, 33, 9, -20, -22};                                // trench
Plane Surface(3) = {3};
Curve Loop(4) = {1, 2, 41, -25, -24, -23};                           // lift-1
Plane Surface(4) = {4};
Curve Loop(5) = {3, 42, -26, -41};                                   // lift-2
Plane Surface(5) = {5};
Curve Loop(6) = {4, 43, -27, -42};                                   // lift-3
Plane Surface(6) = {6};
Curve Loop(7) = {5, 44, -28, -43};                                   // lift-4
Plane Surface(7) = {7};
Curve Loop(8) = {6, 45, -30, -29, -44};                                   // lift-5
Plane Surface(8) = {8};
Curve Loop(9) = {7, 22, -19, -32, -31, -45};                    // lift-6
Plane Surface(9) = {9};

// the subgrade coarsens with depth
Field[1] = Distance;
Field[1].CurvesList = {10, 11, 12, 8, 33, 9, 20, 19, 18};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = fine;
Field[2].SizeMax = coarse;
Field[2].DistMin = 0.5;
Field[2].DistMax = 6;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.Algorithm = 6;

Physical Surface("subgrade") = {2};
Physical Surface("clay") = {1};
Physical Surface("trench") = {3};
Physical Surface("cover") = {4, 5, 6, 7, 8, 9};
Physical Surface("lift-1") = {4};
Physical Surface("lift-2") = {5};
Physical Surface("lift-3") = {6};
Physical Surface("lift-4") = {7};
Physical Surface("lift-5") = {8};
Physical Surface("lift-6") = {9};
Physical Curve("liner") = {1, 2, 3, 4, 5, 6, 7, 8, 33, 9};
Physical Curve("base") = {16};
Physical Curve("sides") = {14, 15, 23, 17};
Physical Curve("cover-top") = {24, 25, 26, 27, 28, 29, 30, 31};
