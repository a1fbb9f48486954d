// panel.cpp: the viewer's control panel (panel.h), a thin adapter over
// Dear ImGui 1.86 and its GLFW and OpenGL 3 backends (Debian libimgui-dev).
// Every number it edits is a field of sss_view_params, so a frame stays a
// pure function of those parameters (app.c); the panel writes a field only
// on the frame its control changed, so a picture the keys made is the one
// the panel leaves alone.
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <initializer_list>

#include "panel.h"
extern "C" {
#include "sss/decode.h"
#include "sss/dipole.h"
#include "sss/field.h"
#include "sss/format.h"
#include "sss/vec3.h"
}

namespace {

// Layout (panel.h): fixed, so that a script can click the controls.
constexpr float kWidth = 300.0f, kMargin = 8.0f;
// Frames of history in the stage graph: about four seconds at 60 Hz.
constexpr int kHistory = 240;
// The gains the keys and the sliders share (app.c clamps to the same range).
constexpr float kGainLo = 1e-4f, kGainHi = 1e4f;

enum { ST_SCATTER, ST_NEAR, ST_DRAW, ST_COUNT };
const char *const kStageName[ST_COUNT] = {"scatter", "near terms", "draw"};
const ImU32 kStageColour[ST_COUNT] = {IM_COL32(90, 170, 250, 255), IM_COL32(250, 170, 60, 255),
                                      IM_COL32(120, 210, 120, 255)};

}  // namespace

struct sss_panel {
    float ms[kHistory][ST_COUNT];  // ring of the stage times, oldest at next
    float frame[kHistory];         // wall-clock frame time
    int next, count;
    ImVec2 pos, size;              // the panel's rectangle on the last frame it was shown (size 0: hidden)
};

namespace {

// Light direction as two angles in the viewer's world frame (y up, the
// same azimuth/elevation the camera orbit uses in app.c): azimuth from +z
// towards +x, elevation above the horizontal plane, in degrees.
void light_angles(const double l[3], float *az, float *el)
{
    double n = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    if (!(n > 0)) { *az = *el = 0; return; }
    double y = l[1] / n;
    *el = (float)(std::asin(y < -1 ? -1 : y > 1 ? 1 : y) * 180.0 / SSS_PI);
    *az = (float)(std::atan2(l[0], l[2]) * 180.0 / SSS_PI);
}

void light_from_angles(float az, float el, double l[3])
{
    double a = az * SSS_PI / 180.0, e = el * SSS_PI / 180.0;
    l[0] = std::cos(e) * std::sin(a);
    l[1] = std::sin(e);
    l[2] = std::cos(e) * std::cos(a);
}

// The smallest of 1, 2, 5 × 10^k at or above x: a graph scale that does
// not jitter with every frame.
float nice_ceiling(float x)
{
    if (!(x > 0)) return 1.0f;
    float p = std::pow(10.0f, std::floor(std::log10(x)));
    for (float m : {1.0f, 2.0f, 5.0f, 10.0f})
        if (m * p >= x) return m * p;
    return 10.0f * p;
}

// A remark in the disabled colour, wrapped at the panel's edge.
void note(const char *fmt, ...) IM_FMTARGS(1);
void note(const char *fmt, ...)
{
    char buf[256];
    va_list ap;
    va_start(ap, fmt);
    std::vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("%s", buf);
    ImGui::PopStyleColor();
}

void bytes_text(const char *label, uint64_t b)
{
    if (b >= (uint64_t)1 << 20) ImGui::Text("%-16s %.2f MiB", label, (double)b / (1 << 20));
    else ImGui::Text("%-16s %.1f KiB", label, (double)b / 1024);
}

// Light: direction, irradiance E per channel as intensity × colour. A
// scene's baked lights keep the directions and places its file gives them;
// an editable object's first light turns (docs/heterogeneous.md §9.1).
void light_section(sss_view_params *p, int scene)
{
    float az, el;
    light_angles(p->light, &az, &el);
    if (scene) {
        note("directions: the scene's own lights");
    } else {
        bool turned = ImGui::SliderFloat("azimuth", &az, -180.0f, 180.0f, "%.1f deg");
        turned |= ImGui::SliderFloat("elevation", &el, -90.0f, 90.0f, "%.1f deg");
        if (turned) light_from_angles(az, el, p->light);
    }
    double e = std::fmax(p->light_rgb[0], std::fmax(p->light_rgb[1], p->light_rgb[2]));
    if (!(e > 0)) e = 1.0;
    float intensity = (float)e;
    float colour[3] = {(float)(p->light_rgb[0] / e), (float)(p->light_rgb[1] / e), (float)(p->light_rgb[2] / e)};
    bool lit = ImGui::SliderFloat("intensity", &intensity, kGainLo, kGainHi, "%.4g", ImGuiSliderFlags_Logarithmic);
    lit |= ImGui::ColorEdit3("colour", colour, ImGuiColorEditFlags_Float);
    if (lit) {
        if (!(intensity > 0)) intensity = kGainLo;
        for (int k = 0; k < 3; k++) p->light_rgb[k] = (double)intensity * (double)std::fmax(colour[k], 0.0f);
    }
}

void image_section(sss_view_params *p)
{
    float x = (float)p->exposure;
    if (ImGui::SliderFloat("exposure", &x, kGainLo, kGainHi, "%.4g", ImGuiSliderFlags_Logarithmic))
        p->exposure = x > 0 ? x : kGainLo;
    int t = (int)p->tonemap;
    ImGui::TextUnformatted("tone map");
    ImGui::SameLine(96);
    if (ImGui::RadioButton("clamp", &t, SSS_TONEMAP_CLAMP)) p->tonemap = SSS_TONEMAP_CLAMP;
    ImGui::SameLine();
    if (ImGui::RadioButton("reinhard", &t, SSS_TONEMAP_REINHARD)) p->tonemap = SSS_TONEMAP_REINHARD;
    int path = (int)p->path;
    ImGui::TextUnformatted("q on the");
    ImGui::SameLine(96);
    if (ImGui::RadioButton("GPU", &path, SSS_EVAL_GPU)) p->path = SSS_EVAL_GPU;
    ImGui::SameLine();
    if (ImGui::RadioButton("CPU", &path, SSS_EVAL_CPU)) p->path = SSS_EVAL_CPU;
    bool w = p->wireframe != 0;
    if (ImGui::Checkbox("wireframe", &w)) p->wireframe = w;
}

// The terms of the picture and the effects of the file (docs/viewer.md).
void effects_section(sss_view_params *p, const sss_panel_info *in)
{
    const sss_bake_file *f = in->f;
    bool s = p->scatter != 0, r = p->specular != 0;
    if (ImGui::Checkbox("scatter", &s)) p->scatter = s;
    ImGui::SameLine(120);
    if (ImGui::Checkbox("specular", &r)) p->specular = r;
    if (f->near_terms) {
        bool o = p->near_terms != 0;
        if (ImGui::Checkbox("near terms", &o)) p->near_terms = o;
        ImGui::SameLine(120);
        int v = p->near_visibility;
        if (ImGui::RadioButton("rays", &v, SSS_NEAR_RAYS)) p->near_visibility = SSS_NEAR_RAYS;
        ImGui::SameLine();
        if (ImGui::RadioButton("map", &v, SSS_NEAR_MAP)) p->near_visibility = SSS_NEAR_MAP;
        if (p->near_visibility == SSS_NEAR_MAP) {
            // powers of two from 256 to 8192: the range --shadow-size accepts
            int lg = (int)std::lround(std::log2((double)(p->shadow_size ? p->shadow_size : SSS_SHADOW_SIZE)));
            char label[16];
            std::snprintf(label, sizeof label, "%d", 1 << lg);
            if (ImGui::SliderInt("shadow map", &lg, 8, 13, label)) p->shadow_size = 1 << lg;
        }
        if (f->near_radius_mm > 0.0) note("near terms: every vertex within %.3g mm", f->near_radius_mm);
        else note("near terms: own + %u ring%s", f->near_rings, f->near_rings == 1 ? "" : "s");
    }
    if (in->scene) {
        ImGui::TextWrapped("scene lights: %s", in->scene_desc ? in->scene_desc : "summed on the CPU");
        if (in->edit) note("each directional light by the run-time path, its own light-space map per frame");
        else note("each light from the effect the file baked for it");
    }
    if (in->scene_eval) {
        // one switch per light kind the scene has (sss_scene_eval_set_kinds):
        // both sums, CPU and GPU, leave a kind that is off out
        static const char *const kKinds[4] = {"static suns (exact)", "moving sun (directions)",
                                              "point lights (shells)", "environment (SH)"};
        const unsigned present = sss_scene_eval_kinds_present(in->scene_eval);
        unsigned on = sss_scene_eval_kinds(in->scene_eval);
        for (unsigned k = 0; k < 4; k++) {
            if (!(present >> k & 1)) continue;
            bool b = (on >> k & 1) != 0;
            if (ImGui::Checkbox(kKinds[k], &b)) on = b ? on | 1u << k : on & ~(1u << k);
        }
        sss_scene_eval_set_kinds(in->scene_eval, on);
    }
    // the surface terms' shadow and their diffuse share (docs/viewer.md,
    // "Direct surface light"), last, so that the boxes above keep their
    // place (tests/integration/window_xvfb.sh and view_scene.sh click them)
    bool sh = p->surface_shadow != 0;
    if (ImGui::Checkbox("surface shadow", &sh)) p->surface_shadow = sh;
    float rho = (float)p->diffuse;
    if (ImGui::SliderFloat("diffuse", &rho, 0.0f, 1.0f, "%.2f")) p->diffuse = rho < 0 ? 0 : rho > 1 ? 1 : rho;
    // q between the direction samples (Hao-Varshney 2004 3.2, Fig. 3)
    int ip = p->interp;
    ImGui::TextUnformatted("q from");
    ImGui::SameLine(96);
    if (ImGui::RadioButton("triangle", &ip, SSS_INTERP_TRIANGLE)) p->interp = SSS_INTERP_TRIANGLE;
    ImGui::SameLine();
    if (ImGui::RadioButton("4 nearest", &ip, SSS_INTERP_NEAREST4)) p->interp = SSS_INTERP_NEAREST4;
}

// An editable object's live material (docs/heterogeneous.md §9.1): the
// inside's absorption, the field's strength and the base's transport
// colour, the keys' edits (J / K, U / I, Y) as sliders, read back from the
// material every frame so that keys and sliders agree.
void edit_section(sss_htsm_material *m, double transport_mm, int *save)
{
    float sa[3];
    for (int c = 0; c < 3; c++) sa[c] = (float)m->inside.sigma_a[c];
    if (ImGui::SliderFloat3("inside s_a", sa, 1e-4f, 10.0f, "%.3g", ImGuiSliderFlags_Logarithmic))
        for (int c = 0; c < 3; c++) m->inside.sigma_a[c] = std::fmin(10.0, std::fmax(1e-4, (double)sa[c]));
    float s = (float)m->strength;
    if (ImGui::SliderFloat("strength", &s, 1.0f / 64, 64.0f, "%.3g", ImGuiSliderFlags_Logarithmic))
        m->strength = std::fmin(64.0, std::fmax(1.0 / 64, (double)s));
    // T_c = exp(-sigma_tr T_d) of the base (the inverse of sss_transport_sigma_a)
    float tc[3];
    for (int c = 0; c < 3; c++) tc[c] = (float)std::exp(-sss_material_sigma_tr(&m->base, &m->base, 0.0, (uint32_t)c) *
                                                        transport_mm);
    if (ImGui::ColorEdit3("transport", tc, ImGuiColorEditFlags_Float)) {
        double col[3], out[3];
        for (int c = 0; c < 3; c++) col[c] = std::fmin(0.99, std::fmax(0.01, (double)tc[c]));
        sss_error err = {{0}};
        if (sss_transport_sigma_a(col, transport_mm, m->base.sigmap_s, out, &err) == SSS_OK)
            std::memcpy(m->base.sigma_a, out, sizeof out);
    }
    note("the base's colour after %.3g mm sets its sigma_a; the inside's sigma'_s %.3g %.3g %.3g /mm", transport_mm,
         m->inside.sigmap_s[0], m->inside.sigmap_s[1], m->inside.sigmap_s[2]);
    // the edit written back as a scene file, as E does (docs/heterogeneous.md 9.6)
    if (save && ImGui::Button("write the scene (E)")) *save = 1;
}

// The material is baked into q: only the exit term is the viewer's (an
// editable object's base is the live one, edited above).
void material_section(sss_view_params *p, const sss_panel_info *in)
{
    const sss_bake_file *f = in->f;
    const sss_material *m = in->edit ? &in->edit->base : &f->material;
    ImGui::Text("%.31s   eta %.3f", m->name, m->eta);
    if (f->channels == 3) {
        ImGui::Text("sigma_a   %.4g %.4g %.4g /mm", m->sigma_a[0], m->sigma_a[1], m->sigma_a[2]);
        ImGui::Text("sigma'_s  %.4g %.4g %.4g /mm", m->sigmap_s[0], m->sigmap_s[1], m->sigmap_s[2]);
    } else {
        ImGui::Text("sigma_a %.4g /mm  sigma'_s %.4g /mm", m->sigma_a[0], m->sigmap_s[0]);
    }
    int x = p->exit_normalised ? 1 : 0;
    ImGui::TextUnformatted("exit term");
    ImGui::SameLine(96);
    if (ImGui::RadioButton("F_t", &x, 0)) p->exit_normalised = 0;
    ImGui::SameLine();
    if (ImGui::RadioButton("F_t / c(eta)", &x, 1)) p->exit_normalised = 1;
    if (in->edit)
        note("c(eta) = %.4f. q is computed each frame from the live material", sss_exit_norm(m->eta));
    else
        note("c(eta) = %.4f. eta, sigma_a and sigma'_s are baked into q: change them with sss-bake",
             sss_exit_norm(m->eta));
}

// The stage times of the last kHistory frames stacked bottom to top
// (scatter, near terms, draw: disjoint timer queries, sss/render.h), on a
// scale of 1, 2 or 5 × 10^k ms that covers the tallest frame.
void times_section(sss_panel *pn, const sss_panel_info *in)
{
    float top = 0, mean[ST_COUNT] = {0, 0, 0}, fmean = 0;
    for (int i = 0; i < pn->count; i++) {
        const float *m = pn->ms[i];
        top = std::fmax(top, m[ST_SCATTER] + m[ST_NEAR] + m[ST_DRAW]);
        for (int s = 0; s < ST_COUNT; s++) mean[s] += m[s];
        fmean += pn->frame[i];
    }
    const float scale = nice_ceiling(top);
    const float w = ImGui::GetContentRegionAvail().x, h = 70.0f;
    const ImVec2 o = ImGui::GetCursorScreenPos();
    ImDrawList *dl = ImGui::GetWindowDrawList();
    dl->AddRectFilled(o, ImVec2(o.x + w, o.y + h), IM_COL32(20, 20, 24, 255));
    const float col = w / kHistory;
    for (int k = 0; k < pn->count; k++) {
        // newest on the right
        const int i = (pn->next - pn->count + k + kHistory) % kHistory;
        float x0 = o.x + (float)(kHistory - pn->count + k) * col, y = o.y + h;
        for (int s = 0; s < ST_COUNT; s++) {
            float dy = h * pn->ms[i][s] / scale;
            if (dy <= 0) continue;
            dl->AddRectFilled(ImVec2(x0, y - dy), ImVec2(x0 + col, y), kStageColour[s]);
            y -= dy;
        }
    }
    dl->AddRect(o, ImVec2(o.x + w, o.y + h), IM_COL32(110, 110, 110, 255));
    ImGui::Dummy(ImVec2(w, h));
    ImGui::Text("scale %.3g ms", scale);
    const float n = pn->count > 0 ? (float)pn->count : 1.0f;
    for (int s = 0; s < ST_COUNT; s++) {
        if (s == ST_NEAR && !in->f->near_terms) continue;
        ImGui::ColorButton(kStageName[s], ImGui::ColorConvertU32ToFloat4(kStageColour[s]),
                           ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoPicker,
                           ImVec2(10, 10));
        ImGui::SameLine();
        ImGui::Text("%-10s %7.3f ms", kStageName[s], mean[s] / n);
    }
    ImGui::Text("frame      %7.2f ms  %.1f fps", fmean / n, fmean > 0 ? 1e3f * n / fmean : 0.0f);
    note("stages: GPU timer queries (the CPU path: wall clock); frame: wall clock, waits included");
    if (in->scene) note("a scene's light sum is not timed by stage");
}

// The file: what it stores and what that costs (format §5, sss_file_storage).
void file_section(const sss_panel_info *in)
{
    const sss_bake_file *f = in->f;
    const char *base = std::strrchr(in->file_path, '/');
    ImGui::TextWrapped("%s", base ? base + 1 : in->file_path);
    ImGui::Text("vertices %u  triangles %u", f->mesh.nv, f->mesh.nf);
    ImGui::Text("channels %u  directions %u", f->channels, f->dirs.n);
    ImGui::TextWrapped("storage %s", in->storage);
    ImGui::Text("bytes/vertex %.1f (scattering data)", in->bytes_per_vertex);
    sss_storage st;
    sss_file_storage(f, &st);
    bytes_text("scattering", st.scattering);
    bytes_text("directions", st.dirs);
    if (st.effects) bytes_text("  of it effects", st.effects);
    bytes_text("total", st.total);
    if (f->fx.mask) {
        char list[256] = "";
        size_t len = 0;
        for (uint32_t k = 0; k < SSS_FX_COUNT && len + 1 < sizeof list; k++)
            if (f->fx.mask >> k & 1u)
                len += (size_t)std::snprintf(list + len, len < sizeof list ? sizeof list - len : 0, "%s%s",
                                             len ? ", " : "", sss_effect_name(k));
        ImGui::TextWrapped("effects: %s", list);
    } else {
        ImGui::TextUnformatted("effects: direction set (plain bake)");
    }
    if (f->near_terms) ImGui::TextUnformatted("near terms: added at run time (OWNT)");
}

}  // namespace

sss_panel *sss_panel_create(struct GLFWwindow *win, sss_error *err)
{
    IMGUI_CHECKVERSION();
    sss_panel *pn = new sss_panel();
    ImGui::CreateContext();
    ImGuiIO &io = ImGui::GetIO();
    io.IniFilename = nullptr;  // fixed layout, nothing written to the working directory
    io.LogFilename = nullptr;
    ImGui::StyleColorsDark();
    ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w = 0.88f;
    // GL 4.3 core at least (app.c): the backend's 4.1 core shaders
    if (!ImGui_ImplGlfw_InitForOpenGL(win, true)) {
        if (err) std::snprintf(err->msg, sizeof err->msg, "the panel's GLFW backend could not start");
        ImGui::DestroyContext();
        delete pn;
        return nullptr;
    }
    if (!ImGui_ImplOpenGL3_Init("#version 410 core")) {
        if (err) std::snprintf(err->msg, sizeof err->msg, "the panel's OpenGL backend could not start");
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        delete pn;
        return nullptr;
    }
    return pn;
}

void sss_panel_destroy(sss_panel *pn)
{
    if (!pn) return;
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    delete pn;
}

void sss_panel_frame(sss_panel *pn, int show, sss_view_params *p, const sss_panel_info *in)
{
    float *m = pn->ms[pn->next];
    m[ST_SCATTER] = (float)in->times.scatter_ms;
    m[ST_NEAR] = (float)in->times.near_ms;
    m[ST_DRAW] = (float)in->times.draw_ms;
    pn->frame[pn->next] = (float)in->frame_ms;
    pn->next = (pn->next + 1) % kHistory;
    if (pn->count < kHistory) pn->count++;

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    pn->size = ImVec2(0, 0);
    if (!show) return;
    const ImVec2 disp = ImGui::GetIO().DisplaySize;
    const float h = std::fmax(disp.y - 2 * kMargin, 60.0f);
    ImGui::SetNextWindowPos(ImVec2(disp.x - kWidth - kMargin, kMargin), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(kWidth, h), ImGuiCond_Always);
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                   ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings |
                                   ImGuiWindowFlags_NoFocusOnAppearing;
    if (ImGui::Begin("sss-view  (G hides)", nullptr, flags)) {
        ImGui::PushItemWidth(-90.0f);  // labels right of the controls get 90 px
        if (ImGui::CollapsingHeader("Light", ImGuiTreeNodeFlags_DefaultOpen)) light_section(p, in->scene && !in->edit);
        if (in->edit && ImGui::CollapsingHeader("Live material", ImGuiTreeNodeFlags_DefaultOpen))
            edit_section(in->edit, in->transport_mm, in->edit_save);
        if (ImGui::CollapsingHeader("Image", ImGuiTreeNodeFlags_DefaultOpen)) image_section(p);
        if (ImGui::CollapsingHeader("Effects", ImGuiTreeNodeFlags_DefaultOpen)) effects_section(p, in);
        if (ImGui::CollapsingHeader("Material", ImGuiTreeNodeFlags_DefaultOpen)) material_section(p, in);
        if (ImGui::CollapsingHeader("Frame time by stage", ImGuiTreeNodeFlags_DefaultOpen)) times_section(pn, in);
        if (ImGui::CollapsingHeader("File", ImGuiTreeNodeFlags_DefaultOpen)) file_section(in);
        ImGui::PopItemWidth();
    }
    pn->pos = ImGui::GetWindowPos();
    pn->size = ImGui::GetWindowSize();
    ImGui::End();
}

void sss_panel_render(sss_panel *pn)
{
    (void)pn;
    ImGui::Render();
    ImDrawData *d = ImGui::GetDrawData();
    if (d && d->CmdListsCount > 0) ImGui_ImplOpenGL3_RenderDrawData(d);
}

int sss_panel_wants_mouse(const sss_panel *pn, double x, double y)
{
    if (ImGui::GetIO().WantCaptureMouse) return 1;
    return pn->size.x > 0 && x >= pn->pos.x && x < pn->pos.x + pn->size.x && y >= pn->pos.y &&
           y < pn->pos.y + pn->size.y;
}

int sss_panel_wants_keyboard(const sss_panel *pn)
{
    (void)pn;
    return ImGui::GetIO().WantTextInput ? 1 : 0;
}
