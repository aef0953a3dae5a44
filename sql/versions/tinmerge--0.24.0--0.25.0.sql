-- tinmerge 0.24.0 -> 0.25.0. Stored values read and answer as before; what
-- is built is built as before. New: tin_area_stats, tin_volume and
-- tin_surface_area, and tin_volume of two tins, answer tins in a
-- geographic SRID in metres on the
-- SRID's spheroid (before: ERROR 22023). The core also holds build engine
-- 2 (issue 74), which no SQL function calls yet.
COMMENT ON FUNCTION tin_area_stats(tin, geometry, int) IS
'Statistics of the surface of a level (NULL = finest) clipped exactly to a POLYGON or MULTIPOLYGON: planar area, surface area, min/max height, area-weighted mean height and slope (degrees), steepest slope. Heights are NULL when the polygon misses the domain. A tin in a geographic SRID (degrees, heights in metres) answers in metres on the SRID''s spheroid: areas in square metres, slopes with the metres a degree spans at each part''s latitude.';
COMMENT ON FUNCTION tin_volume(tin, geometry, float8, int) IS
'Volumes inside a POLYGON or MULTIPOLYGON between the surface of a level (NULL = finest) and the height base_z: cut = volume of surface above base_z, fill = volume of the space below base_z down to the surface (as a cut-and-fill or ArcGIS Surface Volume), exact for the linear surface. A tin in a geographic SRID (degrees, heights in metres) answers in cubic metres on the SRID''s spheroid.';
COMMENT ON FUNCTION tin_surface_area(tin, geometry, int) IS
'Surface (3D) area of a level (NULL = finest) clipped exactly to a POLYGON or MULTIPOLYGON: the area3d of tin_area_stats as a scalar (0 when the polygon misses the domain; NULL when an argument other than level is NULL), so it can be used where a set-returning call cannot, e.g. pushed down to a postgres_fdw shard. A tin in a geographic SRID answers in square metres on the SRID''s spheroid.';
COMMENT ON FUNCTION tin_volume(tin, tin, geometry, int, int) IS
'Cut and fill between two surfaces inside a POLYGON or MULTIPOLYGON (holes count out), each at a level (NULL = finest): two epochs of a survey, or a design against the ground, as ArcGIS Surface Difference and Cut Fill. cut = volume where a is above b, fill = volume where a is below b, area_cut and area_fill the planar areas where it is so, area_unchanged where the two are one plane (their triangles'' planes agree within 1e-9 of the height, as tin_difference); exact for the linear surfaces, over the overlay of the two (tin_overlay) clipped to the polygon. Only the common domain counts: the three areas sum to the polygon''s part of it. The tins must share their SRID and the polygon must have it too; tins in a geographic SRID answer in metres on its spheroid (as tin_area_stats). No row for a NULL tin or polygon.';
