// A 6 m geogrid-reinforced segmental retaining wall (plane strain, per metre width).
//
// - Foundation: 3 m of dense soil from x = -4 (in front of the wall) to x = 16.
// - Facing: a 0.3 m column of segmental blocks, x = 0 to 0.3, from y = 0 to 6.
// - Backfill: reinforced zone x = 0.3 to 4.5, retained fill beyond, to x = 16.
// - Ten lifts of 0.6 m ("lift-1" at the bottom to "lift-10"), each with a geogrid at its
//   mid-height ("grid-1" at y = 0.3 to "grid-10" at y = 5.7), running from the face of the
//   blocks (x = 0) to x = 4.5: a length of 0.75 H behind the facing, 0.6 m vertical spacing.
//
// The mesh is structured (transfinite) 4-node quadrangles, so that every Gmsh version writes the
// same nodes (first order: a reinforcement runs along linear element sides). Regenerate with:
//   gmsh reinforced-wall.geo -2 -format msh41 -o reinforced-wall.msh
// Units: metres.

xs[] = {-4.0, 0.0, 0.3, 4.5, 16.0};
nx[] = {4, 1, 14, 12};
ys[] = {-3.0};
ny[] = {4};
For k In {0:19}
  ys[] += {0.3 * k};
  ny[] += {1};
EndFor
ys[] += {6.0};
NX = #xs[] - 1;
NY = #ys[] - 1;

// point (i, j) exists unless it lies in front of the wall above the ground
For j In {0:NY}
  For i In {0:NX}
    If (!(i == 0 && j > 1))
      Point(1 + i + 10 * j) = {xs[i], ys[j], 0};
    EndIf
  EndFor
EndFor
// horizontal lines h(i, j) and vertical lines v(i, j)
For j In {0:NY}
  For i In {0:NX-1}
    If (!(i == 0 && j > 1))
      Line(1000 + i + 100 * j) = {1 + i + 10 * j, 2 + i + 10 * j};
      Transfinite Curve{1000 + i + 100 * j} = nx[i] + 1;
    EndIf
  EndFor
EndFor
For j In {0:NY-1}
  For i In {0:NX}
    If (!(i == 0 && j > 0))
      Line(5000 + i + 100 * j) = {1 + i + 10 * j, 1 + i + 10 * (j + 1)};
      Transfinite Curve{5000 + i + 100 * j} = ny[j] + 1;
    EndIf
  EndFor
EndFor
// cells
For j In {0:NY-1}
  For i In {0:NX-1}
    If (!(i == 0 && j > 0))
      Curve Loop(10000 + i + 100 * j) = {1000 + i + 100 * j, 5000 + i + 1 + 100 * j, -(1000 + i + 100 * (j + 1)), -(5000 + i + 100 * j)};
      Plane Surface(10000 + i + 100 * j) = {10000 + i + 100 * j};
      Transfinite Surface{10000 + i + 100 * j};
      Recombine Surface{10000 + i + 100 * j};
    EndIf
  EndFor
EndFor

Physical Surface("foundation") = {10000:10003};
facing[] = {};
fill[] = {};
For j In {1:NY-1}
  facing[] += {10001 + 100 * j};
  fill[] += {10002 + 100 * j, 10003 + 100 * j};
EndFor
Physical Surface("facing") = {facing[]};
Physical Surface("fill") = {fill[]};
For k In {1:10}
  Physical Surface(Sprintf("lift-%g", k)) = {10001 + 100 * (2 * k - 1), 10002 + 100 * (2 * k - 1), 10003 + 100 * (2 * k - 1),
                                             10001 + 100 * (2 * k), 10002 + 100 * (2 * k), 10003 + 100 * (2 * k)};
  // the geogrid of lift k at y = 0.6 k - 0.3: through the facing and into the backfill
  Physical Curve(Sprintf("grid-%g", k)) = {1001 + 100 * (2 * k), 1002 + 100 * (2 * k)};
EndFor
Physical Curve("base") = {1000:1003};
Physical Curve("sides") = {5000, 5004:5004 + 100 * (NY - 1):100};
face[] = {};
For j In {1:NY-1}
  face[] += {5001 + 100 * j};
EndFor
Physical Curve("face") = {face[]};
Physical Curve("top") = {1002 + 100 * NY, 1003 + 100 * NY};

