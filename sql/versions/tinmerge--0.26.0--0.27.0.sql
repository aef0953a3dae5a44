-- tinmerge 0.26.0 -> 0.27.0. Stored values read and answer as before. The
-- Rust functions that call PostGIS or read its spatial_ref_sys find them in
-- PostGIS's schema (looked up in pg_extension once per backend) and no
-- longer pin a search_path: a function with a SET clause pays a
-- configuration change on every call.
ALTER FUNCTION tin_area_triangles(tin, geometry, int, boolean) RESET search_path;
ALTER FUNCTION tin_area_stats(tin, geometry, int) RESET search_path;
ALTER FUNCTION tin_volume(tin, geometry, float8, int) RESET search_path;
ALTER FUNCTION tin_surface_area(tin, geometry, int) RESET search_path;
ALTER FUNCTION tin_volume(tin, tin, geometry, int, int) RESET search_path;
ALTER FUNCTION tin_slope_aspect(tin, int) RESET search_path;
ALTER FUNCTION tin_line_of_sight(tin, geometry, geometry, float8, float8, int, boolean, float8) RESET search_path;
ALTER FUNCTION tin_quantized_mesh(tin, int, int, int, boolean, float8, geometry, boolean) RESET search_path;
ALTER FUNCTION tin_quantized_mesh(tin, int, int, int, int, boolean, float8, geometry, boolean) RESET search_path;
ALTER FUNCTION tin_quantized_mesh_layer(tin, boolean, boolean, text, boolean, boolean) RESET search_path;
ALTER FUNCTION tin_quantized_mesh(tin[], int, int, int, boolean, float8, geometry, boolean) RESET search_path;
ALTER FUNCTION tin_quantized_mesh_layer(tin[], boolean, boolean, text, boolean, boolean) RESET search_path;
