// Laboratory geogrid pull-out box (plane strain, per metre width), after ASTM D6706.
//
// A 1.5 m long, 0.6 m high box of sand with a geogrid at mid-height. The grid leaves the box through a
// 50 mm slot in the front wall (x = 0) and is embedded over 1.2 m; behind its tail the sand is
// continuous. An airbag loads the top. Units: metres.
//
// The mesh is structured (transfinite) 50 mm quadrangles, so that every Gmsh version writes the same
// nodes. Regenerate with:  gmsh lab-pullout.geo -2 -format msh41 -o lab-pullout.msh
// (geoslip does this itself when the model's mesh.file names this .geo).

h = 0.05;            // element size [m]
L_box = 1.5;         // box length
H = 0.6;             // box height
y_grid = 0.3;        // geogrid level
L_grid = 1.2;        // embedded length
slot = 0.025;        // half-height of the front slot

Point(1) = {0, 0, 0};
Point(2) = {L_box, 0, 0};
Point(3) = {L_box, y_grid, 0};
Point(4) = {L_grid, y_grid, 0};     // geogrid tail
Point(5) = {0, y_grid, 0};          // geogrid head, in the slot
Point(6) = {0, y_grid - slot, 0};   // slot, lower edge
Point(7) = {L_box, H, 0};
Point(8) = {0, H, 0};
Point(9) = {0, y_grid + slot, 0};   // slot, upper edge

Line(1) = {1, 2};    // floor
Line(2) = {2, 3};    // back wall, lower
Line(3) = {3, 4};    // sand-sand behind the tail
Line(4) = {4, 5};    // geogrid
Line(5) = {5, 6};    // slot, lower
Line(6) = {6, 1};    // front wall, lower
Line(7) = {3, 7};    // back wall, upper
Line(8) = {7, 8};    // airbag
Line(9) = {8, 9};    // front wall, upper
Line(10) = {9, 5};   // slot, upper

Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {-4, -3, 7, 8, 9, 10};
Plane Surface(2) = {2};

n_x = Round(L_box / h);
n_grid = Round(L_grid / h);
n_y = Round(y_grid / h);
n_slot = Round(slot / h);
Transfinite Curve{1, 8} = n_x + 1;
Transfinite Curve{4} = n_grid + 1;
Transfinite Curve{3} = n_x - n_grid + 1;
Transfinite Curve{2, 7} = n_y + 1;
Transfinite Curve{5, 10} = n_slot + 1;
Transfinite Curve{6, 9} = n_y - n_slot + 1;
Transfinite Surface{1} = {1, 2, 3, 5};
Transfinite Surface{2} = {5, 3, 7, 8};
Recombine Surface{1, 2};

Physical Surface("sand") = {1, 2};
Physical Curve("floor") = {1};
Physical Curve("back") = {2, 7};
Physical Curve("front") = {6, 9};
Physical Curve("airbag") = {8};
Physical Curve("geogrid") = {4};
