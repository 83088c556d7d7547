// Geogrid pull-out box drawn as engineers draw it (plane strain, per metre width): one continuous
// body of sand with the geogrid line embedded in it, the grid leaving the box at the front wall.
// Units: metres.
//
// The grid is a curve inside the surface ("Curve In Surface"), so the mesh follows it and its nodes
// are the sand's; the sand is not cut. Regenerate with:
//   gmsh embedded-pullout.geo -2 -format msh41 -o embedded-pullout.msh
// (geoslip does this itself when the model's mesh.file names this .geo).

h = 0.05;            // element size [m]
L_box = 1.5;         // box length
H = 0.6;             // box height
y_grid = 0.3;        // geogrid level
L_grid = 1.2;        // embedded length

Point(1) = {0, 0, 0, h};
Point(2) = {L_box, 0, 0, h};
Point(3) = {L_box, H, 0, h};
Point(4) = {0, H, 0, h};
Point(5) = {0, y_grid, 0, h};        // geogrid head, on the front wall
Point(6) = {L_grid, y_grid, 0, h};   // geogrid tail, inside the sand

Line(1) = {1, 2};    // floor
Line(2) = {2, 3};    // back wall
Line(3) = {3, 4};    // airbag
Line(4) = {4, 5};    // front wall, upper
Line(5) = {5, 1};    // front wall, lower
Line(6) = {5, 6};    // geogrid

Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Curve{6} In Surface{1};

Transfinite Curve{6} = Round(L_grid / h) + 1;
Recombine Surface{1};

Physical Surface("sand") = {1};
Physical Curve("floor") = {1};
Physical Curve("back") = {2};
Physical Curve("airbag") = {3};
Physical Curve("front") = {4, 5};
Physical Curve("geogrid") = {6};
