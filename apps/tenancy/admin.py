"""Fleets and their tokens in the admin. A token's key is shown once, in the message after it is created:
only its hash and first characters are stored. Failed admin logins are throttled like the dashboard's."""

from django.contrib import admin, messages
from django.utils.html import format_html

from .login import ThrottledAdminAuthenticationForm
from .models import Fleet, FleetToken

admin.site.login_form = ThrottledAdminAuthenticationForm

TOKEN_FIELDS = ["fleet", "user", "scope", "description", "expires"]
TOKEN_READONLY = ["prefix", "created", "last_used"]


def show_new_key(request, token: FleetToken) -> None:
    if token.plaintext:
        messages.warning(
            request,
            format_html(
                "New token for {}: <code>{}</code> — copy it now, it is stored only as a hash and will not be "
                "shown again.",
                token.fleet,
                token.plaintext,
            ),
        )


class FleetTokenInline(admin.TabularInline):
    model = FleetToken
    extra = 0
    fields = ["prefix", "user", "scope", "description", "expires", "created", "last_used"]
    readonly_fields = TOKEN_READONLY
    autocomplete_fields = ["user"]


@admin.register(Fleet)
class FleetAdmin(admin.ModelAdmin):
    list_display = ["name", "slug", "created"]
    search_fields = ["name", "slug"]
    prepopulated_fields = {"slug": ["name"]}
    filter_horizontal = ["members"]
    inlines = [FleetTokenInline]

    def save_formset(self, request, form, formset, change) -> None:
        super().save_formset(request, form, formset, change)
        for obj in formset.new_objects:
            if isinstance(obj, FleetToken):
                show_new_key(request, obj)


@admin.register(FleetToken)
class FleetTokenAdmin(admin.ModelAdmin):
    list_display = ["prefix", "fleet", "user", "scope", "description", "created", "expires", "last_used"]
    list_filter = ["fleet", "scope"]
    search_fields = ["prefix", "description", "fleet__name", "user__username"]
    fields = TOKEN_FIELDS + TOKEN_READONLY
    readonly_fields = TOKEN_READONLY
    autocomplete_fields = ["user"]

    def save_model(self, request, obj, form, change) -> None:
        super().save_model(request, obj, form, change)
        if not change:
            show_new_key(request, obj)
