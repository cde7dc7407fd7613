// The VTK backend: a Scene in, a PNG out, with no X server.
//
// Why it is built this way. Debian's VTK 9.1 is compiled for X windows only, and odec must
// draw on machines with no display (CI, servers, a user's ssh session). So odec makes its
// own off-screen GL context (gl_context.h: OSMesa, or EGL surfaceless) and lends it to a
// vtkGenericOpenGLRenderWindow: that window class never creates a context of its own but
// asks its observers whether it is current, whether OpenGL is supported and how to make its
// context current, and the observers below answer from our context. The window renders
// off-screen into framebuffer objects, and vtkWindowToImageFilter reads the picture back
// from them (the context's own buffer is a token and is never read).
//
// The context and the window are expensive the first time (Mesa compiles VTK's shaders)
// and cheap afterwards, so they live for the whole process: a warm picture of ten thousand
// blocks costs a few tens of milliseconds. Each picture clears the props of the previous one
// and builds its own small pipeline; nothing from one picture leaks into the next, so the
// same scene gives the same pixels whatever was drawn before.
//
// The frame is laid out by hand: a title strip at the top, a column per colour legend on the
// right, the model fitted into what is left (its own renderer and viewport, so a legend never
// hides a block), and a small axes triad in the lower left. Charts (histories) replace the
// model with a vtkChartXY drawn by the same window.
//
// Determinism: colour tables are computed here from fixed control points, no
// multisampling, fixed fonts, and the camera is derived from the scene alone.
#include "render/vtk_backend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <unordered_map>

#include <unistd.h>

#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkArrowSource.h>
#include <vtkAxesActor.h>
#include <vtkAxis.h>
#include <vtkBrush.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCaptionActor2D.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkCommand.h>
#include <vtkContextActor.h>
#include <vtkContextScene.h>
#include <vtkCylinderSource.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkGlyph3D.h>
#include <vtkIdTypeArray.h>
#include <vtkLight.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotLine.h>
#include <vtkPlotPoints.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty.h>
#include <vtkProperty2D.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkTable.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkVariant.h>
#include <vtkWindowToImageFilter.h>

namespace odec::render {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct Backend {
    std::unique_ptr<GlContext> context;
    vtkSmartPointer<vtkGenericOpenGLRenderWindow> window;
    vtkSmartPointer<vtkRenderer> back;   // layer 0: background, title, legends, charts
    vtkSmartPointer<vtkRenderer> model;  // layer 1: the 3D model, in its own viewport
    vtkSmartPointer<vtkRenderer> triad;  // layer 2: axes triad
    vtkSmartPointer<vtkRenderer> labels; // layer 3: labels over the model, seen through it (its camera)
    std::string description;
};

Backend* g_backend = nullptr;
bool g_kind_chosen = false;
GlContextKind g_kind = GlContextKind::OSMesa;
RenderTimes g_times;

// Observers through which the generic window learns about the context we own.
void on_make_current(vtkObject*, unsigned long, void* client, void*) {
    static_cast<Backend*>(client)->context->make_current();
}
void on_is_current(vtkObject*, unsigned long, void* client, void* call) {
    *static_cast<bool*>(call) = static_cast<Backend*>(client)->context->is_current();
}
void on_supports_gl(vtkObject*, unsigned long, void*, void* call) { *static_cast<int*>(call) = 1; }
void on_is_direct(vtkObject*, unsigned long, void*, void* call) { *static_cast<int*>(call) = 1; }
void on_frame(vtkObject*, unsigned long, void*, void*) {} // nothing to swap off-screen

void observe(vtkObject* obj, unsigned long event, void (*fn)(vtkObject*, unsigned long, void*, void*),
             Backend* b) {
    vtkNew<vtkCallbackCommand> cb;
    cb->SetCallback(fn);
    cb->SetClientData(b);
    obj->AddObserver(event, cb);
}

Backend* start_backend(std::string& error) {
    if (!g_kind_chosen) {
        g_kind = default_gl_context_kind();
        g_kind_chosen = true;
    }
    auto b = std::make_unique<Backend>();
    b->context = create_gl_context(g_kind, error);
    if (!b->context) return nullptr;

    b->window = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
    vtkGenericOpenGLRenderWindow* w = b->window;
    observe(w, vtkCommand::WindowMakeCurrentEvent, on_make_current, b.get());
    observe(w, vtkCommand::WindowIsCurrentEvent, on_is_current, b.get());
    observe(w, vtkCommand::WindowSupportsOpenGLEvent, on_supports_gl, b.get());
    observe(w, vtkCommand::WindowIsDirectEvent, on_is_direct, b.get());
    observe(w, vtkCommand::WindowFrameEvent, on_frame, b.get());
    w->SetOffScreenRendering(1);
    w->SetMultiSamples(0);
    w->SetSize(640, 480);
    w->SetReadyForRendering(true);
    w->SetIsCurrent(true);
    w->SetMapped(1);
    w->SetNumberOfLayers(4);
    if (!w->InitializeFromCurrentContext()) {
        error = std::string(b->context->name()) + ": VTK could not initialise OpenGL in the off-screen context";
        w->SetReadyForRendering(false);
        return nullptr;
    }

    b->back = vtkSmartPointer<vtkRenderer>::New();
    b->back->SetLayer(0);
    b->model = vtkSmartPointer<vtkRenderer>::New();
    b->model->SetLayer(1);
    // One light that moves with the camera, from above and a little right of the eye, so the
    // tops of blocks read brightest (as under daylight) and the faces of a block differ.
    b->model->AutomaticLightCreationOff();
    vtkNew<vtkLight> light;
    light->SetLightTypeToCameraLight();
    light->SetPosition(0.25, 0.6, 1.0);
    light->SetFocalPoint(0, 0, 0);
    light->SetIntensity(1.0);
    b->model->AddLight(light);
    b->triad = vtkSmartPointer<vtkRenderer>::New();
    b->triad->SetLayer(2);
    b->triad->InteractiveOff();
    b->labels = vtkSmartPointer<vtkRenderer>::New();
    b->labels->SetLayer(3);
    b->labels->InteractiveOff();
    b->labels->SetActiveCamera(b->model->GetActiveCamera());
    w->AddRenderer(b->back);
    w->AddRenderer(b->model);
    w->AddRenderer(b->triad);
    w->AddRenderer(b->labels);

    const char* version = w->ReportCapabilities();
    std::string caps = version ? version : "";
    // The interesting part of the report: "OpenGL version string: ..." and the renderer.
    auto field = [&](const char* key) {
        const auto at = caps.find(key);
        if (at == std::string::npos) return std::string();
        const auto from = at + std::string(key).size();
        return caps.substr(from, caps.find('\n', from) - from);
    };
    b->description = std::string(b->context->name()) + ": OpenGL " + field("OpenGL version string:  ") +
                     " (" + field("OpenGL renderer string:  ") + ")";
    return b.release();
}

double luminance(const Rgb& c) { return 0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]; }

Rgb text_colour(const Rgb& background) {
    return luminance(background) > 0.5 ? Rgb{0.08, 0.08, 0.08} : Rgb{0.95, 0.95, 0.95};
}

void style_text(vtkTextProperty* p, const Rgb& colour, int size, bool bold = false) {
    p->SetFontFamilyToArial();
    p->SetColor(colour[0], colour[1], colour[2]);
    p->SetFontSize(size);
    p->SetBold(bold);
    p->SetItalic(false);
    p->SetShadow(false);
}

bool has_legend(const ColourScale& s, bool has_scalars) { return has_scalars && s.legend; }

// A lookup table over lo..hi from our own colour tables (Categorical: one entry per category).
vtkSmartPointer<vtkLookupTable> make_lookup_table(const ColourScale& scale) {
    auto lut = vtkSmartPointer<vtkLookupTable>::New();
    if (scale.map == ColourMap::Categorical) {
        const int n = std::max<int>(1, static_cast<int>(scale.categories.size()));
        lut->SetNumberOfTableValues(n);
        for (int k = 0; k < n; ++k) {
            const Rgb c = category_colour(scale, k);
            lut->SetTableValue(k, c[0], c[1], c[2], 1.0);
            const std::string name = k < static_cast<int>(scale.categories.size()) ? scale.categories[k]
                                                                                  : std::to_string(k);
            lut->SetAnnotation(vtkVariant(k), name);
        }
        lut->SetTableRange(0, n - 1);
        lut->IndexedLookupOn();
        return lut;
    }
    const int n = 256;
    lut->SetNumberOfTableValues(n);
    for (int k = 0; k < n; ++k) {
        const Rgb c = colour_at(scale.map, static_cast<double>(k) / (n - 1));
        lut->SetTableValue(k, c[0], c[1], c[2], 1.0);
    }
    double lo = scale.lo, hi = scale.hi;
    if (!(hi > lo)) hi = lo + std::max(1e-12, std::abs(lo) * 1e-9); // one colour: the low end
    lut->SetTableRange(lo, hi);
    lut->SetBelowRangeColor(0, 0, 0, 1);
    lut->SetAboveRangeColor(0, 0, 0, 1);
    return lut;
}

vtkSmartPointer<vtkDoubleArray> to_array(const std::vector<double>& v, const char* name) {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->SetNumberOfTuples(static_cast<vtkIdType>(v.size()));
    for (size_t i = 0; i < v.size(); ++i) a->SetValue(static_cast<vtkIdType>(i), v[i]);
    return a;
}

vtkSmartPointer<vtkPoints> to_points(const std::vector<Vec3>& pts) {
    auto p = vtkSmartPointer<vtkPoints>::New();
    p->SetDataTypeToDouble();
    p->SetNumberOfPoints(static_cast<vtkIdType>(pts.size()));
    for (size_t i = 0; i < pts.size(); ++i) p->SetPoint(static_cast<vtkIdType>(i), pts[i].data());
    return p;
}

void style_surface(vtkActor* actor) {
    vtkProperty* p = actor->GetProperty();
    // Mostly ambient so that colours read true against the legend; enough diffuse that
    // the faces of a block are told apart.
    p->SetAmbient(0.5);
    p->SetDiffuse(0.55);
    p->SetSpecular(0.0);
    p->SetInterpolationToFlat();
}

struct Bounds {
    double b[6] = {1e300, -1e300, 1e300, -1e300, 1e300, -1e300};
    void add(const Vec3& x) {
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(x[k])) return;
        }
        for (int k = 0; k < 3; ++k) {
            b[2 * k] = std::min(b[2 * k], x[k]);
            b[2 * k + 1] = std::max(b[2 * k + 1], x[k]);
        }
    }
    bool valid() const { return b[0] <= b[1]; }
    double diagonal() const {
        if (!valid()) return 0;
        return std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
                         (b[5] - b[4]) * (b[5] - b[4]));
    }
};

// Faces of a closed, opaque layer that some other solid covers exactly: a joint face seen
// from both of its blocks. They are never visible, and in a jointed rock mass they are most
// faces; drawing them costs llvmpipe dearly because VTK's shaders write depth (for the
// polygon offset of edges), which defeats early depth rejection.
std::vector<char> shared_faces(const PolygonLayer& layer, double tol) {
    const int n_polys = static_cast<int>(layer.offsets.size()) - 1;
    std::vector<char> shared(static_cast<size_t>(std::max(n_polys, 0)), 0);
    if (!(tol > 0)) return shared;
    std::unordered_map<std::string, int> first_with_key;
    std::vector<std::array<long long, 3>> q;
    std::string key;
    for (int f = 0; f < n_polys; ++f) {
        q.clear();
        for (int i = layer.offsets[f]; i < layer.offsets[f + 1]; ++i) {
            const Vec3& x = layer.points[layer.indices[i]];
            q.push_back({std::llround(x.x() / tol), std::llround(x.y() / tol), std::llround(x.z() / tol)});
        }
        std::sort(q.begin(), q.end());
        key.assign(reinterpret_cast<const char*>(q.data()), q.size() * sizeof q[0]);
        auto [it, inserted] = first_with_key.emplace(key, f);
        if (!inserted) {
            shared[f] = 1;
            if (it->second >= 0) shared[it->second] = 1;
        }
    }
    return shared;
}

vtkSmartPointer<vtkActor> polygon_actor(const PolygonLayer& layer, double model_size,
                                        vtkSmartPointer<vtkLookupTable>& lut_out) {
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    poly->SetPoints(to_points(layer.points));
    const int n_polys = layer.offsets.empty() ? 0 : static_cast<int>(layer.offsets.size()) - 1;
    const bool cell = !layer.cell_scalars.empty() && static_cast<int>(layer.cell_scalars.size()) == n_polys;
    const bool point = !cell && !layer.point_scalars.empty() && layer.point_scalars.size() == layer.points.size();
    const bool solid = layer.closed && layer.opacity >= 1.0;
    const std::vector<char> skip = solid ? shared_faces(layer, 1e-7 * model_size) : std::vector<char>(n_polys, 0);

    auto offsets = vtkSmartPointer<vtkIdTypeArray>::New();
    auto conn = vtkSmartPointer<vtkIdTypeArray>::New();
    offsets->InsertNextValue(0);
    std::vector<double> kept_scalars;
    for (int f = 0; f < n_polys; ++f) {
        if (skip[f]) continue;
        for (int i = layer.offsets[f]; i < layer.offsets[f + 1]; ++i) conn->InsertNextValue(layer.indices[i]);
        offsets->InsertNextValue(conn->GetNumberOfTuples());
        if (cell) kept_scalars.push_back(layer.cell_scalars[f]);
    }
    auto cells = vtkSmartPointer<vtkCellArray>::New();
    cells->SetData(offsets, conn);
    poly->SetPolys(cells);

    auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
    mapper->SetInputData(poly);
    if (cell || point) {
        lut_out = make_lookup_table(layer.scale);
        if (cell) {
            poly->GetCellData()->SetScalars(to_array(kept_scalars, "value"));
            mapper->SetScalarModeToUseCellData();
        } else {
            poly->GetPointData()->SetScalars(to_array(layer.point_scalars, "value"));
            mapper->SetScalarModeToUsePointData();
            mapper->InterpolateScalarsBeforeMappingOn(); // true contours across a polygon
        }
        mapper->SetLookupTable(lut_out);
        mapper->UseLookupTableScalarRangeOn();
        mapper->ScalarVisibilityOn();
        mapper->SetColorModeToMapScalars();
    } else {
        mapper->ScalarVisibilityOff();
    }
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    style_surface(actor);
    vtkProperty* p = actor->GetProperty();
    p->SetColor(layer.flat_colour[0], layer.flat_colour[1], layer.flat_colour[2]);
    p->SetOpacity(layer.opacity);
    if (!layer.lit) p->LightingOff();
    // A closed solid's faces that turn away are hidden by its front faces.
    if (solid) p->BackfaceCullingOn();
    if (layer.edges && !(layer.mesh && layer.opacity < 1.0)) {
        p->EdgeVisibilityOn();
        p->SetEdgeColor(layer.edge_colour[0], layer.edge_colour[1], layer.edge_colour[2]);
        p->SetLineWidth(static_cast<float>(layer.edge_width));
    }
    return actor;
}

// Glyph source along +x from 0 to 1 (arrow) or centred on 0 (bar).
vtkSmartPointer<vtkPolyDataAlgorithm> glyph_source(GlyphLayer::Shape shape) {
    if (shape == GlyphLayer::Shape::Arrow) {
        auto arrow = vtkSmartPointer<vtkArrowSource>::New();
        arrow->SetTipResolution(16);
        arrow->SetShaftResolution(12);
        arrow->SetTipLength(0.3);
        arrow->SetTipRadius(0.09);
        arrow->SetShaftRadius(0.035);
        return arrow;
    }
    auto cyl = vtkSmartPointer<vtkCylinderSource>::New(); // along y, centred
    cyl->SetResolution(10);
    cyl->SetHeight(1.0);
    cyl->SetRadius(0.05);
    cyl->CappingOn();
    vtkNew<vtkTransform> t;
    t->RotateZ(-90.0); // y axis onto x
    auto tf = vtkSmartPointer<vtkTransformPolyDataFilter>::New();
    tf->SetTransform(t);
    tf->SetInputConnection(cyl->GetOutputPort());
    return tf;
}

vtkSmartPointer<vtkActor> glyph_actor(const GlyphLayer& layer, double fallback_length,
                                      vtkSmartPointer<vtkLookupTable>& lut_out) {
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    poly->SetPoints(to_points(layer.origins));
    auto dirs = vtkSmartPointer<vtkDoubleArray>::New();
    dirs->SetName("direction");
    dirs->SetNumberOfComponents(3);
    dirs->SetNumberOfTuples(static_cast<vtkIdType>(layer.directions.size()));
    double max_norm = 0;
    for (size_t i = 0; i < layer.directions.size(); ++i) {
        dirs->SetTuple(static_cast<vtkIdType>(i), layer.directions[i].data());
        max_norm = std::max(max_norm, layer.directions[i].norm());
    }
    poly->GetPointData()->SetVectors(dirs);
    const bool coloured = layer.scalars.size() == layer.origins.size() && !layer.scalars.empty();
    if (coloured) poly->GetPointData()->SetScalars(to_array(layer.scalars, "value"));

    auto glyph = vtkSmartPointer<vtkGlyph3D>::New();
    glyph->SetInputData(poly);
    glyph->SetSourceConnection(glyph_source(layer.shape)->GetOutputPort());
    glyph->OrientOn();
    glyph->SetVectorModeToUseVector();
    glyph->SetScaleModeToScaleByVector();
    const double length = layer.max_length > 0 ? layer.max_length : fallback_length;
    glyph->SetScaleFactor(max_norm > 0 ? length / max_norm : 0.0);
    glyph->SetColorModeToColorByScalar();

    auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
    mapper->SetInputConnection(glyph->GetOutputPort());
    if (coloured) {
        lut_out = make_lookup_table(layer.scale);
        mapper->SetLookupTable(lut_out);
        mapper->UseLookupTableScalarRangeOn();
        mapper->SetScalarModeToUsePointData();
        mapper->ScalarVisibilityOn();
    } else {
        mapper->ScalarVisibilityOff();
    }
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    style_surface(actor);
    actor->GetProperty()->SetInterpolationToGouraud();
    actor->GetProperty()->SetColor(layer.flat_colour[0], layer.flat_colour[1], layer.flat_colour[2]);
    return actor;
}

vtkSmartPointer<vtkActor> line_actor(const LineLayer& layer) {
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    poly->SetPoints(to_points(layer.points));
    auto lines = vtkSmartPointer<vtkCellArray>::New();
    for (const auto& s : layer.segments) {
        const vtkIdType ids[2] = {s[0], s[1]};
        lines->InsertNextCell(2, ids);
    }
    poly->SetLines(lines);
    auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
    mapper->SetInputData(poly);
    mapper->ScalarVisibilityOff();
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    vtkProperty* p = actor->GetProperty();
    p->SetColor(layer.colour[0], layer.colour[1], layer.colour[2]);
    p->SetLineWidth(static_cast<float>(layer.width));
    p->LightingOff();
    return actor;
}

// Legend titles are wrapped at spaces into short lines so the legend column stays narrow.
std::string legend_title(const ColourScale& s) {
    std::string t = s.title.empty() ? std::string("value") : s.title;
    if (!s.units.empty()) t += " (" + s.units + ")";
    const size_t max_line = 14;
    std::string out, line;
    size_t from = 0;
    while (from <= t.size()) {
        size_t to = t.find(' ', from);
        if (to == std::string::npos) to = t.size();
        const std::string word = t.substr(from, to - from);
        if (!line.empty() && line.size() + 1 + word.size() > max_line) {
            out += (out.empty() ? "" : "\n") + line;
            line = word;
        } else {
            line += (line.empty() ? "" : " ") + word;
        }
        from = to + 1;
    }
    if (!line.empty()) out += (out.empty() ? "" : "\n") + line;
    return out;
}

// Width in pixels a legend needs: its widest title line or label, plus the colour bar.
int legend_width_px(const ColourScale& s, int font) {
    size_t chars = 9; // "-1.23e-05"
    const std::string t = legend_title(s);
    size_t from = 0;
    while (from <= t.size()) {
        size_t to = t.find('\n', from);
        if (to == std::string::npos) to = t.size();
        chars = std::max(chars, to - from);
        from = to + 1;
    }
    for (const auto& c : s.categories) chars = std::max(chars, c.size() + 4);
    return static_cast<int>(chars * font * 0.62) + font * 3;
}

vtkSmartPointer<vtkScalarBarActor> legend_actor(const ColourScale& scale, vtkLookupTable* lut, const Rgb& fg,
                                                int font, double x, double y, double w, double h) {
    auto bar = vtkSmartPointer<vtkScalarBarActor>::New();
    bar->SetLookupTable(lut);
    bar->SetTitle(legend_title(scale).c_str());
    bar->SetOrientationToVertical();
    bar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    bar->GetPositionCoordinate()->SetValue(x, y);
    bar->GetPosition2Coordinate()->SetCoordinateSystemToNormalizedViewport();
    bar->GetPosition2Coordinate()->SetValue(w, h);
    bar->UnconstrainedFontSizeOn();
    bar->SetTextPositionToSucceedScalarBar();
    bar->SetBarRatio(scale.map == ColourMap::Categorical ? 0.18 : 0.28);
    bar->SetVerticalTitleSeparation(font / 2);
    bar->SetTextPad(4);
    bar->SetMaximumNumberOfColors(256);
    style_text(bar->GetTitleTextProperty(), fg, font, true);
    bar->GetTitleTextProperty()->SetJustificationToLeft();
    style_text(bar->GetLabelTextProperty(), fg, font);
    style_text(bar->GetAnnotationTextProperty(), fg, font);
    if (scale.map == ColourMap::Categorical) {
        // Annotations go opposite the tick labels: precede, so the names sit right of the swatches.
        bar->SetTextPositionToPrecedeScalarBar();
        bar->DrawAnnotationsOn();
        bar->DrawTickLabelsOff();
        bar->SetAnnotationLeaderPadding(4);
        bar->FixedAnnotationLeaderLineColorOn();
    } else {
        bar->DrawAnnotationsOff();
        bar->SetNumberOfLabels(6);
        bar->SetLabelFormat("%-.3g"); // one format for every label: 3 significant figures
    }
    return bar;
}

// A legend of named colours (group, material, region, contact state): a swatch and a name
// per category, top-down from (x, y_top) in pixels. Drawn by hand because the scalar bar's
// annotations crowd and clip when the names are long.
void add_category_legend(Backend& b, const ColourScale& scale, const Rgb& fg, int font, int x, int y_top) {
    vtkNew<vtkTextActor> title;
    title->SetInput(legend_title(scale).c_str());
    style_text(title->GetTextProperty(), fg, font, true);
    title->GetTextProperty()->SetVerticalJustificationToTop();
    title->SetDisplayPosition(x, y_top);
    b.back->AddActor2D(title);
    const std::string wrapped = legend_title(scale);
    const int n_title_lines = 1 + static_cast<int>(std::count(wrapped.begin(), wrapped.end(), '\n'));
    int y = y_top - static_cast<int>(font * (1.3 * n_title_lines + 0.6));
    const int side = static_cast<int>(font * 1.15);
    for (size_t k = 0; k < scale.categories.size(); ++k) {
        const Rgb c = category_colour(scale, static_cast<int>(k));
        vtkNew<vtkPoints> pts;
        pts->InsertNextPoint(x, y - side, 0);
        pts->InsertNextPoint(x + side, y - side, 0);
        pts->InsertNextPoint(x + side, y, 0);
        pts->InsertNextPoint(x, y, 0);
        vtkNew<vtkCellArray> quad;
        const vtkIdType ids[4] = {0, 1, 2, 3};
        quad->InsertNextCell(4, ids);
        vtkNew<vtkPolyData> poly;
        poly->SetPoints(pts);
        poly->SetPolys(quad);
        vtkNew<vtkPolyDataMapper2D> mapper;
        mapper->SetInputData(poly);
        vtkNew<vtkActor2D> swatch;
        swatch->SetMapper(mapper);
        swatch->GetProperty()->SetColor(c[0], c[1], c[2]);
        b.back->AddActor2D(swatch);

        vtkNew<vtkTextActor> name;
        name->SetInput(scale.categories[k].c_str());
        style_text(name->GetTextProperty(), fg, font);
        name->GetTextProperty()->SetVerticalJustificationToCentered();
        name->SetDisplayPosition(x + side + font / 2, y - side / 2);
        b.back->AddActor2D(name);
        y -= static_cast<int>(side * 1.45);
    }
}

// Title strip: first line large and bold, the rest (step, time) smaller beneath.
double add_title(Backend& b, const std::string& title, const Rgb& fg, int width, int height, int font) {
    if (title.empty()) return 0;
    const auto nl = title.find('\n');
    const std::string head = title.substr(0, nl);
    const std::string rest = nl == std::string::npos ? std::string() : title.substr(nl + 1);
    const int pad = std::max(6, height / 80);
    int y = height - pad;
    auto put = [&](const std::string& text, int size, bool bold) {
        if (text.empty()) return;
        vtkNew<vtkTextActor> t;
        t->SetInput(text.c_str());
        style_text(t->GetTextProperty(), fg, size, bold);
        t->GetTextProperty()->SetVerticalJustificationToTop();
        t->GetTextProperty()->SetJustificationToLeft();
        t->SetDisplayPosition(pad + 4, y);
        b.back->AddActor2D(t);
        const int n_lines = 1 + static_cast<int>(std::count(text.begin(), text.end(), '\n'));
        y -= static_cast<int>(n_lines * size * 1.25);
    };
    put(head, static_cast<int>(font * 1.35), true);
    put(rest, font, false);
    (void)width;
    return static_cast<double>(height - y + pad) / height;
}

// Aim the camera and fit what is drawn into the viewport exactly (ResetCamera fits a
// bounding sphere, which leaves a box-shaped model small in the frame and a long thin one
// smaller still). `fit` are the points that must be seen; `aspect` is viewport width/height.
void place_camera(vtkRenderer* r, const Camera& cam, const Bounds& bounds, const std::vector<Vec3>& fit,
                  double aspect) {
    vtkCamera* c = r->GetActiveCamera();
    const Vec3 centre((bounds.b[0] + bounds.b[1]) / 2, (bounds.b[2] + bounds.b[3]) / 2,
                      (bounds.b[4] + bounds.b[5]) / 2);
    Vec3 dir = cam.eye_given ? Vec3(cam.eye_point - centre) : cam.eye_direction;
    if (!(dir.norm() > 0)) dir = Vec3(1, -1, 0.8);
    dir.normalize();
    Vec3 up = cam.up;
    if (!(up.norm() > 0) || std::abs(up.normalized().dot(dir)) > 0.999) {
        // Looking along the up vector (plan views): y up on the screen.
        up = std::abs(dir.dot(Vec3(0, 1, 0))) > 0.999 ? Vec3(0, 0, 1) : Vec3(0, 1, 0);
    }
    up = (up - up.dot(dir) * dir).normalized();
    const Vec3 right = (-dir).cross(up);
    const double margin = 1.1 / (cam.zoom > 0 ? cam.zoom : 1.0);
    const double diag = std::max(bounds.diagonal(), 1e-9);
    c->SetParallelProjection(cam.parallel && !cam.eye_given);

    if (cam.eye_given) {
        // An eye point is where the user stands: keep it, aim at the model, open the view
        // angle until everything is in.
        const Vec3 eye = cam.eye_point;
        double need = 0.05;
        for (const Vec3& p : fit) {
            const Vec3 q = p - eye;
            const double depth = q.dot(-dir);
            if (depth <= 1e-9 * diag) continue;
            need = std::max({need, std::abs(q.dot(up)) / depth, std::abs(q.dot(right)) / (depth * aspect)});
        }
        const double angle = 2 * std::atan(need * margin) * 180.0 / M_PI;
        c->SetPosition(eye.data());
        c->SetFocalPoint(centre.data());
        c->SetViewUp(up.data());
        c->SetViewAngle(std::min(150.0, std::max(5.0, angle)));
        r->ResetCameraClippingRange(const_cast<double*>(bounds.b));
        return;
    }

    // Extent on the screen, then centre on it.
    double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
    for (const Vec3& p : fit) {
        const Vec3 q = p - centre;
        x_lo = std::min(x_lo, q.dot(right));
        x_hi = std::max(x_hi, q.dot(right));
        y_lo = std::min(y_lo, q.dot(up));
        y_hi = std::max(y_hi, q.dot(up));
    }
    if (x_lo > x_hi) x_lo = x_hi = y_lo = y_hi = 0;
    const Vec3 focal = centre + 0.5 * (x_lo + x_hi) * right + 0.5 * (y_lo + y_hi) * up;
    const double half_x = std::max(0.5 * (x_hi - x_lo), 1e-9 * diag), half_y = std::max(0.5 * (y_hi - y_lo), 1e-9 * diag);
    double distance = 2 * diag;
    if (!c->GetParallelProjection()) {
        // Each point must lie within the view cone: its offset over its distance from the eye.
        const double t = std::tan(15.0 * M_PI / 180.0); // half of the 30 degree view angle
        distance = 0;
        for (const Vec3& p : fit) {
            const Vec3 q = p - focal;
            distance = std::max(distance, q.dot(dir) + margin * std::max(std::abs(q.dot(up)) / t,
                                                                         std::abs(q.dot(right)) / (t * aspect)));
        }
        distance = std::max(distance, 1e-6 * diag);
    }
    const Vec3 pos = focal + dir * distance;
    c->SetFocalPoint(focal.data());
    c->SetPosition(pos.data());
    c->SetViewUp(up.data());
    c->SetViewAngle(30);
    c->SetParallelScale(margin * std::max(half_y, half_x / aspect));
    r->ResetCameraClippingRange(const_cast<double*>(bounds.b));
}

void place_triad(Backend& b, const Rgb& fg, int height) {
    // A fresh triad each time: its captions keep positions from the frame before.
    vtkNew<vtkAxesActor> axes;
    axes->SetShaftTypeToCylinder();
    axes->SetCylinderRadius(0.04);
    axes->SetConeRadius(0.35);
    axes->SetTotalLength(1, 1, 1);
    axes->AxisLabelsOn();
    for (vtkCaptionActor2D* cap : {axes->GetXAxisCaptionActor2D(), axes->GetYAxisCaptionActor2D(),
                                   axes->GetZAxisCaptionActor2D()}) {
        vtkTextProperty* p = cap->GetCaptionTextProperty();
        style_text(p, fg, std::max(10, height / 50), true);
        cap->GetTextActor()->SetTextScaleModeToNone();
    }
    b.triad->AddActor(axes);
    vtkCamera* mc = b.model->GetActiveCamera();
    double dop[3];
    mc->GetDirectionOfProjection(dop);
    vtkCamera* tc = b.triad->GetActiveCamera();
    tc->SetFocalPoint(0, 0, 0);
    tc->SetPosition(-dop[0] * 6, -dop[1] * 6, -dop[2] * 6);
    tc->SetViewUp(mc->GetViewUp());
    tc->SetParallelProjection(false);
    b.triad->ComputeAspect();
    b.triad->ResetCamera(-0.2, 1.2, -0.2, 1.2, -0.2, 1.2);
}

void clear_props(Backend& b) {
    b.back->RemoveAllViewProps();
    b.model->RemoveAllViewProps();
    b.triad->RemoveAllViewProps();
    b.labels->RemoveAllViewProps();
    b.model->DrawOn();
    b.triad->DrawOn();
}

const Rgb kSeriesColours[] = {{0.122, 0.467, 0.706}, {0.839, 0.153, 0.157}, {0.173, 0.627, 0.173},
                              {1.000, 0.498, 0.055}, {0.580, 0.404, 0.741}, {0.549, 0.337, 0.294},
                              {0.890, 0.467, 0.761}, {0.498, 0.498, 0.498}};

bool build_chart(Backend& b, const Scene& scene, const Rgb& fg, int font, std::string& error) {
    b.model->DrawOff();
    b.triad->DrawOff();
    b.back->SetViewport(0, 0, 1, 1);
    vtkNew<vtkChartXY> chart;
    chart->SetAutoSize(true);
    chart->SetShowLegend(true);
    // The legend sits inside the plot: put it in the corner the curves leave emptiest.
    double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
    {
        for (const auto& sr : scene.chart.series)
            for (size_t i = 0; i < std::min(sr.x.size(), sr.y.size()); ++i) {
                x_lo = std::min(x_lo, sr.x[i]);
                x_hi = std::max(x_hi, sr.x[i]);
                y_lo = std::min(y_lo, sr.y[i]);
                y_hi = std::max(y_hi, sr.y[i]);
            }
        int count[4] = {0, 0, 0, 0}; // top right, top left, bottom right, bottom left
        for (const auto& sr : scene.chart.series)
            for (size_t i = 0; i < std::min(sr.x.size(), sr.y.size()); ++i) {
                const double u = x_hi > x_lo ? (sr.x[i] - x_lo) / (x_hi - x_lo) : 0.5;
                const double v = y_hi > y_lo ? (sr.y[i] - y_lo) / (y_hi - y_lo) : 0.5;
                if (v > 0.65 && u > 0.5) ++count[0];
                if (v > 0.65 && u < 0.5) ++count[1];
                if (v < 0.35 && u > 0.5) ++count[2];
                if (v < 0.35 && u < 0.5) ++count[3];
            }
        const int best = static_cast<int>(std::min_element(count, count + 4) - count);
        chart->GetLegend()->SetHorizontalAlignment(best % 2 == 0 ? vtkChartLegend::RIGHT : vtkChartLegend::LEFT);
        chart->GetLegend()->SetVerticalAlignment(best < 2 ? vtkChartLegend::TOP : vtkChartLegend::BOTTOM);
    }
    chart->GetLegend()->SetLabelSize(font);
    chart->GetLegend()->GetBrush()->SetColorF(1, 1, 1, 0.85);
    chart->SetTitle(scene.title.c_str());
    style_text(chart->GetTitleProperties(), fg, static_cast<int>(font * 1.25), true);

    vtkAxis* axes[2] = {chart->GetAxis(vtkAxis::BOTTOM), chart->GetAxis(vtkAxis::LEFT)};
    const std::string titles[2] = {scene.chart.x_label, scene.chart.y_label};
    for (int k = 0; k < 2; ++k) {
        axes[k]->SetTitle(titles[k]);
        style_text(axes[k]->GetTitleProperties(), fg, font, true);
        style_text(axes[k]->GetLabelProperties(), fg, static_cast<int>(font * 0.9));
        axes[k]->SetNotation(vtkAxis::PRINTF_NOTATION);
        axes[k]->SetLabelFormat("%g");
        axes[k]->GetGridPen()->SetColorF(0.85, 0.85, 0.85);
        axes[k]->GetPen()->SetColorF(fg[0], fg[1], fg[2]);
        // A quantity that never changed: give its axis some height, or every label reads the same.
        const double lo = k == 0 ? x_lo : y_lo, hi = k == 0 ? x_hi : y_hi;
        if (lo <= hi && hi - lo <= 1e-12 * std::max(1.0, std::abs(lo))) {
            const double pad = lo != 0 ? 0.1 * std::abs(lo) : 1.0;
            axes[k]->SetBehavior(vtkAxis::FIXED);
            axes[k]->SetRange(lo - pad, hi + pad);
        }
    }
    int n_plotted = 0;
    for (size_t s = 0; s < scene.chart.series.size(); ++s) {
        const ChartSeries& series = scene.chart.series[s];
        const size_t n = std::min(series.x.size(), series.y.size());
        if (n == 0) continue;
        vtkNew<vtkTable> table;
        auto xs = to_array(std::vector<double>(series.x.begin(), series.x.begin() + n), "x");
        auto ys = to_array(std::vector<double>(series.y.begin(), series.y.begin() + n),
                           series.name.empty() ? ("series " + std::to_string(s + 1)).c_str() : series.name.c_str());
        table->AddColumn(xs);
        table->AddColumn(ys);
        auto* plot = vtkPlotLine::SafeDownCast(chart->AddPlot(vtkChart::LINE));
        if (!plot) continue;
        plot->SetInputData(table, 0, 1);
        plot->SetMarkerStyle(scene.chart.markers || n == 1 ? vtkPlotPoints::CIRCLE : vtkPlotPoints::NONE);
        plot->SetMarkerSize(7);
        const Rgb& c = kSeriesColours[s % (sizeof kSeriesColours / sizeof kSeriesColours[0])];
        plot->SetColor(c[0], c[1], c[2]);
        plot->SetWidth(2.0);
        ++n_plotted;
    }
    if (n_plotted == 0) {
        error = "the chart has no samples to draw";
        return false;
    }
    vtkNew<vtkContextActor> actor;
    actor->GetScene()->AddItem(chart);
    b.back->AddActor(actor);
    return true;
}

bool build_model(Backend& b, const Scene& scene, const Rgb& fg, int font, double title_h) {
    Bounds bounds;
    std::vector<Vec3> fit; // what the camera must show
    auto add = [&](const Vec3& x) {
        bounds.add(x);
        fit.push_back(x);
    };
    for (const auto& l : scene.polygons)
        for (const auto& x : l.points) add(x);
    for (const auto& l : scene.lines)
        for (const auto& x : l.points) add(x);
    for (const auto& l : scene.labels) add(l.at);
    for (const auto& g : scene.glyphs)
        for (const auto& x : g.origins) add(x);
    if (!bounds.valid()) return false;
    // A point-like model (one glyph) still needs a frame.
    if (bounds.diagonal() < 1e-12) {
        for (int k = 0; k < 3; ++k) {
            bounds.b[2 * k] -= 0.5;
            bounds.b[2 * k + 1] += 0.5;
        }
    }
    // Glyphs drawn without a given length: a tenth of the model's size for the largest.
    const double fallback = 0.1 * bounds.diagonal();
    for (const auto& g : scene.glyphs) {
        double max_norm = 0;
        for (const auto& d : g.directions) max_norm = std::max(max_norm, d.norm());
        const double len = g.max_length > 0 ? g.max_length : fallback;
        if (max_norm <= 0) continue;
        for (size_t i = 0; i < g.origins.size() && i < g.directions.size(); ++i) {
            const double f = g.shape == GlyphLayer::Shape::Bar ? 0.5 * len / max_norm : len / max_norm;
            add(g.origins[i] + g.directions[i] * f);
            if (g.shape == GlyphLayer::Shape::Bar) add(g.origins[i] - g.directions[i] * f);
        }
    }

    struct Legend {
        const ColourScale* scale;
        vtkSmartPointer<vtkLookupTable> lut;
    };
    std::vector<Legend> legends;
    for (const auto& layer : scene.polygons) {
        if (layer.offsets.size() < 2) continue;
        vtkSmartPointer<vtkLookupTable> lut;
        b.model->AddActor(polygon_actor(layer, bounds.diagonal(), lut));
        if (lut && has_legend(layer.scale, true)) legends.push_back({&layer.scale, lut});
    }
    for (const auto& layer : scene.glyphs) {
        if (layer.origins.empty() || layer.directions.size() != layer.origins.size()) continue;
        vtkSmartPointer<vtkLookupTable> lut;
        b.model->AddActor(glyph_actor(layer, fallback, lut));
        if (lut && has_legend(layer.scale, true)) legends.push_back({&layer.scale, lut});
    }
    for (const auto& layer : scene.lines) {
        if (layer.segments.empty()) continue;
        b.model->AddActor(line_actor(layer));
    }
    for (const auto& label : scene.labels) {
        vtkNew<vtkBillboardTextActor3D> t;
        t->SetInput(label.text.c_str());
        double at[3] = {label.at.x(), label.at.y(), label.at.z()};
        t->SetPosition(at);
        style_text(t->GetTextProperty(), fg, font, true);
        t->GetTextProperty()->SetJustificationToCentered();
        t->GetTextProperty()->SetVerticalJustificationToCentered();
        b.labels->AddActor(t); // drawn over the model: a label at a centroid is inside its block
    }

    // One legend column per coloured layer on the right; the model fills the rest.
    const int width = scene.width, height = scene.height;
    double right = 1.0;
    for (const auto& l : legends) right -= static_cast<double>(legend_width_px(*l.scale, font)) / width;
    right = std::max(0.4, right);
    const double top = 1.0 - title_h;
    double x = right;
    for (const auto& l : legends) {
        const double column = static_cast<double>(legend_width_px(*l.scale, font)) / width;
        const double h = std::min(0.58, top - 0.1);
        const double y = 0.5 * (top - h);
        if (l.scale->map == ColourMap::Categorical)
            add_category_legend(b, *l.scale, fg, font, static_cast<int>(x * width), static_cast<int>((y + h) * height));
        else
            b.back->AddActor2D(legend_actor(*l.scale, l.lut, fg, font, x, y, column, h));
        x += column;
    }
    const double vp_w = std::max(0.4, right), vp_h = std::max(0.4, top);
    b.model->SetViewport(0, 0, vp_w, vp_h);
    b.labels->SetViewport(0, 0, vp_w, vp_h);
    const double aspect = (vp_w * width) / (vp_h * height);
    place_camera(b.model, scene.camera, bounds, fit, aspect);
    b.labels->ResetCameraClippingRange(const_cast<double*>(bounds.b));
    const double triad_size = std::min(0.18, 130.0 / std::max(1, std::min(width, height)) + 0.05);
    // Lower right: below the legends when there are any, where the frame is otherwise empty.
    const double triad_w = triad_size * height / std::max(1, width);
    b.triad->SetViewport(1.0 - triad_w, 0, 1.0, triad_size);
    place_triad(b, fg, height);
    return true;
}

} // namespace

bool render_png(const Scene& scene, const std::string& path, std::string& error) {
    const auto t_start = Clock::now();
    RenderTimes times;
    if (scene.width < 16 || scene.height < 16 || scene.width > 16384 || scene.height > 16384) {
        error = "picture size must be between 16 and 16384 pixels (got " + std::to_string(scene.width) + " x " +
                std::to_string(scene.height) + ")";
        return false;
    }
    if (!g_backend) {
        const auto t0 = Clock::now();
        g_backend = start_backend(error);
        if (!g_backend) return false;
        times.context_ms = ms_since(t0);
    }
    Backend& b = *g_backend;
    const auto t_build = Clock::now();
    b.context->make_current();
    b.window->SetSize(scene.width, scene.height);
    clear_props(b);
    const Rgb& bg = scene.background;
    const Rgb fg = text_colour(bg);
    b.back->SetBackground(bg[0], bg[1], bg[2]);
    b.back->SetViewport(0, 0, 1, 1);
    const int font = std::max(11, std::min(scene.width, scene.height * 4 / 3) / 52);
    if (scene.is_chart()) {
        // A chart has only text to carry: a size larger reads better.
        if (!build_chart(b, scene, fg, font * 6 / 5, error)) return false;
    } else {
        const double title_h = add_title(b, scene.title, fg, scene.width, scene.height, font);
        if (!build_model(b, scene, fg, font, title_h)) {
            error = "nothing to draw: the picture has no blocks, glyphs or lines";
            clear_props(b);
            return false;
        }
    }
    times.build_ms = ms_since(t_build);

    const auto t_draw = Clock::now();
    b.window->Render();
    times.draw_ms = ms_since(t_draw);

    const auto t_write = Clock::now();
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(b.window);
    grab->SetInputBufferTypeToRGB();
    grab->ReadFrontBufferOff();
    grab->ShouldRerenderOff();
    grab->Update();
    const std::string tmp = path + ".tmp" + std::to_string(static_cast<long>(getpid()));
    // Find out first whether the file can be made: VTK would only log an error of its own.
    if (FILE* probe = std::fopen(tmp.c_str(), "wb")) {
        std::fclose(probe);
    } else {
        error = "cannot write '" + path + "'";
        clear_props(b);
        return false;
    }
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(tmp.c_str());
    writer->SetCompressionLevel(4); // a little larger than the default 5, and quicker
    writer->SetInputConnection(grab->GetOutputPort());
    writer->Write();
    const bool written = writer->GetErrorCode() == 0;
    if (!written || std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        error = "cannot write '" + path + "'";
        clear_props(b);
        return false;
    }
    // Drop this picture's pipeline now: its memory is not needed until the next picture.
    clear_props(b);
    times.write_ms = ms_since(t_write);
    times.total_ms = ms_since(t_start);
    g_times = times;
    return true;
}

RenderTimes last_render_times() { return g_times; }

std::string renderer_description() { return g_backend ? g_backend->description : std::string(); }

void set_gl_context_kind(GlContextKind kind) {
    if (g_backend && g_kind != kind) shutdown_renderer();
    g_kind = kind;
    g_kind_chosen = true;
}

void shutdown_renderer() {
    if (!g_backend) return;
    Backend* b = g_backend;
    g_backend = nullptr;
    b->context->make_current();
    clear_props(*b);
    b->window->RemoveRenderer(b->triad);
    b->window->RemoveRenderer(b->model);
    b->window->RemoveRenderer(b->back);
    b->window->Finalize(); // releases GL objects: the context must still be alive
    b->window->SetReadyForRendering(false);
    b->window = nullptr;
    b->back = b->model = b->triad = nullptr;
    b->context.reset();
    delete b;
}

} // namespace odec::render
