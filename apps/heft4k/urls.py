from django.urls import path

from . import views

app_name = "heft4k"
urlpatterns = [
    path("schedules/<int:pk>/what-if/", views.whatif, name="whatif"),
    path("schedules/<int:pk>/simulate/", views.simulate, name="simulate"),
    path("remaps/", views.remap_list, name="remaps"),
    path("remaps/<int:pk>/", views.remap_detail, name="remap"),
    path("remaps/<int:pk>/apply/", views.remap_apply, name="remap-apply"),
]
