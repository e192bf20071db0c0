// Keeps sdvi_fit a valid library while its modules land; the fit owners remove it.
namespace sdvi {
void FitModulePresent() {}
}  // namespace sdvi
